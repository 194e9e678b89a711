// hos-sfm: photos -> registered cameras and undistorted images (COLMAP).
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>

#include "apps/stage_main.h"
#include "core/error.h"
#include "core/exit_codes.h"
#include "sfm/sfm.h"
#include "sfm/sfm_report.h"

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  hos::sfm::SfmOptions options;
  hos::OptionSet option_set("sfm");
  register_options(option_set, options);
  hos::sfm::SfmInput input;
  hos::apps::CommonStageFlags flags;

  CLI::App app{"hos-sfm: cameras from photos with COLMAP; writes WS/sfm/undistorted (images + PINHOLE model)"};
  app.add_option("--images", input.images, "folder of photos (or the images of --sparse)");
  app.add_option("--workspace", input.workspace, "workspace folder; the stage writes WS/sfm/");
  app.add_option("--sparse", input.existing_model, "existing COLMAP sparse model of --images: skip SfM");
  hos::apps::add_common_stage_flags(app, flags, option_set);
  if (const auto code = hos::apps::parse_stage_command_line(app, argc, argv, flags, option_set)) return *code;
  if (input.images.empty() || input.workspace.empty()) {
    std::cerr << "hos-sfm: error: --images and --workspace are required (see --help)\n";
    return hos::kExitUsage;
  }
  if (flags.log_file.empty()) {
    std::error_code ec;
    fs::create_directories(input.workspace / "logs", ec);
    if (!ec) flags.log_file = (input.workspace / "logs" / "sfm.log").string();
  }
  return hos::apps::run_stage_main("sfm", flags, [&](hos::Reporter& reporter) {
    hos::apps::apply_config_and_overrides(option_set, flags);
    const hos::sfm::SfmResult result = hos::sfm::run_sfm(input, options, reporter);
    hos::sfm::write_sfm_report(result, hos::sfm::sfm_paths(input.workspace).report);
    for (const auto& line : hos::sfm::sfm_summary_lines(result)) reporter.info(line);
  });
}
