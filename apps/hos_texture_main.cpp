// hos-texture: mesh + undistorted workspace -> textured binary glTF.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "apps/stage_main.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/exit_codes.h"
#include "core/ply_io.h"
#include "core/undistorted_workspace.h"
#include "core/view_range.h"
#include "texture/model_writer.h"
#include "texture/texture_mesh.h"
#include "texture/texture_output.h"
#include "texture/texture_report.h"

int main(int argc, char** argv) {
  hos::texture::TextureOptions options;
  hos::OptionSet option_set("texture");
  register_options(option_set, options);
  hos::apps::CommonStageFlags flags;
  std::string mesh_path, workspace_path, output_path, report_path, views, view_data, from_view_data;
  std::string geo_path;
  std::vector<std::string> scale_distance;

  CLI::App app{"hos-texture: view selection, seam leveling and texture atlas; writes a .glb"};
  app.add_option("--mesh", mesh_path, "mesh PLY (model coordinates of the workspace)");
  app.add_option("--workspace", workspace_path, "undistorted workspace (images/ + sparse/ PINHOLE model)");
  app.add_option("--output", output_path,
                 "output model, format by extension: .glb, .gltf (+ .bin + atlases), .obj (+ .mtl + atlases), .ply");
  app.add_option("--report", report_path, "also write the stage's figures as JSON (incl. the root matrix)");
  // Job splitting (docs/scale.md): view chunks in parallel jobs, then one join.
  app.add_option("--views", views,
                 "only compute the per-view data (visibility, face samples) of the views FIRST-LAST (0-based, in "
                 "image id order) into --view-data; no --output");
  app.add_option("--view-data", view_data, "folder for the per-view data of --views");
  app.add_option("--from-view-data", from_view_data,
                 "texture from the per-view data --views wrote into this folder (every view's) into --output");
  // Placement (texture/placement.h).
  app.add_option("--geo", geo_path,
                 "JSON with the photos' GPS positions (\"photos\": [{name, gps}], as WS/sfm/report.json has them): "
                 "the model in metres, east-north-up, when they spread far enough");
  app.add_option("--scale-distance", scale_distance,
                 "A.jpg B.jpg METRES: the distance between two photos' camera centres measured on site sets the scale "
                 "(texture.scale_distance)")
      ->expected(3);
  hos::apps::add_common_stage_flags(app, flags, option_set);
  if (const auto code = hos::apps::parse_stage_command_line(app, argc, argv, flags, option_set)) return *code;
  const bool split = !views.empty();
  if (mesh_path.empty() || workspace_path.empty() || (output_path.empty() != split) || (split != !view_data.empty()) ||
      (split && !from_view_data.empty())) {
    std::cerr << "hos-texture: error: --mesh, --workspace and --output are required; or --mesh, --workspace, --views "
                 "and --view-data (see --help)\n";
    return hos::kExitUsage;
  }
  const std::optional<hos::ViewRange> range = split ? hos::parse_view_range(views) : std::nullopt;
  if (split && !range) {
    std::cerr << "hos-texture: error: --views " << views << ": expected FIRST-LAST or INDEX, e.g. 0-9\n";
    return hos::kExitUsage;
  }

  return hos::apps::run_stage_main("texture", flags, [&](hos::Reporter& reporter) {
    hos::apps::apply_config_and_overrides(option_set, flags);
    if (!scale_distance.empty()) {
      options.scale_distance = scale_distance[0] + " " + scale_distance[1] + " " + scale_distance[2];
    }
    options.validate();
    if (!split && !hos::texture::model_format_of(output_path)) {
      throw hos::ConfigError(output_path, std::string("the output must be ") + hos::texture::model_formats_text());
    }
    if (!split) hos::check_writable_target(output_path);  // before the work, not after
    const hos::TriangleMesh mesh = hos::read_mesh_ply(mesh_path);
    const hos::UndistortedWorkspace workspace = hos::load_undistorted_workspace(workspace_path);
    hos::texture::PlacementInput placement;
    if (!geo_path.empty()) placement.photo_positions = hos::texture::read_photo_positions(geo_path);
    if (split) {
      hos::texture::compute_view_data(mesh, workspace, options, reporter, *range, view_data);
      return;
    }
    const hos::texture::TextureResult result =
        from_view_data.empty()
            ? hos::texture::texture_mesh(mesh, workspace, options, reporter, placement)
            : hos::texture::texture_mesh_from_view_data(mesh, workspace, options, reporter, from_view_data, placement);
    hos::texture::write_texture_outputs(output_path, result, options, reporter);
    if (!report_path.empty()) hos::texture::write_texture_report(report_path, result);
    hos::texture::log_texture_summary(result, reporter);
    reporter.info("wrote " + output_path);
  });
}
