// hos-mvs: undistorted workspace -> dense oriented points PLY.
#include <CLI/CLI.hpp>
#include <iostream>
#include <optional>

#include "apps/stage_main.h"
#include "core/atomic_file.h"
#include "core/exit_codes.h"
#include "core/ply_io.h"
#include "core/undistorted_workspace.h"
#include "core/view_range.h"
#include "mvs/mvs_report.h"
#include "mvs/run_mvs.h"

int main(int argc, char** argv) {
  hos::mvs::MvsOptions options;
  hos::OptionSet option_set("mvs");
  register_options(option_set, options);
  hos::apps::CommonStageFlags flags;
  std::string workspace_path, output_path, depth_maps, report_path, views, fuse;

  CLI::App app{"hos-mvs: CPU PatchMatch multi-view stereo; writes dense oriented points"};
  app.add_option("--workspace", workspace_path, "undistorted workspace (images/ + sparse/ PINHOLE model)");
  app.add_option("--output", output_path, "output PLY (x y z nx ny nz red green blue confidence)");
  app.add_option("--depth-maps", depth_maps, "also write every depth and normal map into this folder");
  app.add_option("--report", report_path, "also write the stage's figures as JSON (coverage per view, confidence)");
  // Job splitting (docs/scale.md): view chunks in parallel jobs, then one fusion.
  app.add_option("--views", views,
                 "only compute the depth maps of the views FIRST-LAST (0-based, in image id order) into "
                 "--depth-maps; no fusion, no --output");
  app.add_option("--fuse", fuse, "fuse the depth maps --views wrote into this folder into --output");
  hos::apps::add_common_stage_flags(app, flags, option_set);
  if (const auto code = hos::apps::parse_stage_command_line(app, argc, argv, flags, option_set)) return *code;
  const bool split = !views.empty();
  if (workspace_path.empty() || (output_path.empty() != split) || (split && depth_maps.empty()) ||
      (split && !fuse.empty())) {
    std::cerr << "hos-mvs: error: --workspace and --output are required; or --workspace, --views and --depth-maps "
                 "(see --help)\n";
    return hos::kExitUsage;
  }
  const std::optional<hos::ViewRange> range = split ? hos::parse_view_range(views) : std::nullopt;
  if (split && !range) {
    std::cerr << "hos-mvs: error: --views " << views << ": expected FIRST-LAST or INDEX, e.g. 0-9\n";
    return hos::kExitUsage;
  }

  return hos::apps::run_stage_main("mvs", flags, [&](hos::Reporter& reporter) {
    hos::apps::apply_config_and_overrides(option_set, flags);
    options.validate();
    const hos::UndistortedWorkspace workspace = hos::load_undistorted_workspace(workspace_path);
    if (split) {
      hos::mvs::compute_depth_maps(workspace, options, reporter, *range, depth_maps);
      return;
    }
    hos::check_writable_target(output_path);  // before the work, not after
    const hos::mvs::MvsResult result = fuse.empty()
                                           ? hos::mvs::run_mvs(workspace, options, reporter, depth_maps)
                                           : hos::mvs::fuse_depth_map_folder(workspace, options, reporter, fuse);
    hos::write_point_cloud_ply(output_path, result.points);
    if (!report_path.empty()) hos::mvs::write_mvs_report(report_path, result);
    reporter.info(hos::format_message("wrote ", output_path, ": ", result.points.size(), " points"));
  });
}
