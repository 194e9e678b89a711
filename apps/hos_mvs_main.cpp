// hos-mvs: undistorted workspace -> dense oriented points PLY.
#include <CLI/CLI.hpp>
#include <iostream>

#include "apps/stage_main.h"
#include "core/atomic_file.h"
#include "core/exit_codes.h"
#include "core/ply_io.h"
#include "core/undistorted_workspace.h"
#include "mvs/mvs_report.h"
#include "mvs/run_mvs.h"

int main(int argc, char** argv) {
  hos::mvs::MvsOptions options;
  hos::OptionSet option_set("mvs");
  register_options(option_set, options);
  hos::apps::CommonStageFlags flags;
  std::string workspace_path, output_path, depth_maps, report_path;

  CLI::App app{"hos-mvs: CPU PatchMatch multi-view stereo; writes dense oriented points"};
  app.add_option("--workspace", workspace_path, "undistorted workspace (images/ + sparse/ PINHOLE model)");
  app.add_option("--output", output_path, "output PLY (x y z nx ny nz red green blue confidence)");
  app.add_option("--depth-maps", depth_maps, "also write every depth and normal map into this folder");
  app.add_option("--report", report_path, "also write the stage's figures as JSON (coverage per view, confidence)");
  hos::apps::add_common_stage_flags(app, flags, option_set);
  if (const auto code = hos::apps::parse_stage_command_line(app, argc, argv, flags, option_set)) return *code;
  if (workspace_path.empty() || output_path.empty()) {
    std::cerr << "hos-mvs: error: --workspace and --output are required (see --help)\n";
    return hos::kExitUsage;
  }

  return hos::apps::run_stage_main("mvs", flags, [&](hos::Reporter& reporter) {
    hos::apps::apply_config_and_overrides(option_set, flags);
    options.validate();
    hos::check_writable_target(output_path);  // before the work, not after
    const hos::UndistortedWorkspace workspace = hos::load_undistorted_workspace(workspace_path);
    const hos::mvs::MvsResult result = hos::mvs::run_mvs(workspace, options, reporter, depth_maps);
    hos::write_point_cloud_ply(output_path, result.points);
    if (!report_path.empty()) hos::mvs::write_mvs_report(report_path, result);
    reporter.info(hos::format_message("wrote ", output_path, ": ", result.points.size(), " points"));
  });
}
