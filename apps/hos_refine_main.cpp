// hos-refine: recon mesh + undistorted workspace -> photometrically refined mesh PLY.
#include <CLI/CLI.hpp>
#include <iostream>

#include "apps/stage_main.h"
#include "core/exit_codes.h"
#include "refine/run_refine.h"

int main(int argc, char** argv) {
  hos::refine::RefineOptions options;
  hos::OptionSet option_set("refine");
  register_options(option_set, options);
  hos::apps::CommonStageFlags flags;
  std::string mesh_path, workspace_path, output_path;

  CLI::App app{
      "hos-refine: moves the mesh until the photos agree on it (ZNCC), with a thin-plate "
      "regulariser"};
  app.add_option("--mesh", mesh_path, "mesh PLY (model coordinates of the workspace)");
  app.add_option("--workspace", workspace_path, "undistorted workspace (images/ + sparse/ PINHOLE model)");
  app.add_option("--output", output_path, "refined mesh PLY");
  hos::apps::add_common_stage_flags(app, flags, option_set);
  if (const auto code = hos::apps::parse_stage_command_line(app, argc, argv, flags, option_set)) return *code;
  if (mesh_path.empty() || workspace_path.empty() || output_path.empty()) {
    std::cerr << "hos-refine: error: --mesh, --workspace and --output are required (see --help)\n";
    return hos::kExitUsage;
  }

  return hos::apps::run_stage_main("refine", flags, [&](hos::Reporter& reporter) {
    hos::apps::apply_config_and_overrides(option_set, flags);
    options.validate();
    hos::refine::run_refine(mesh_path, workspace_path, output_path, options, reporter);
  });
}
