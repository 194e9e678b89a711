// hos-recon: oriented points (or registered range scans) -> watertight mesh PLY;
// in tiles when the grid does not fit, also split over processes (--tile K,
// then --join-tiles; docs/scale.md).
#include <CLI/CLI.hpp>
#include <iostream>
#include <sstream>

#include "apps/stage_main.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/exit_codes.h"
#include "core/huge_pages.h"
#include "core/ply_io.h"
#include "recon/recon_report.h"
#include "recon/reconstruct.h"
#include "recon/scans.h"
#include "recon/tile_function_file.h"
#include "recon/tiled_reconstruction.h"

namespace {

// Parses "x,y,z"; throws ConfigError naming the flag.
Eigen::Vector3f parse_vector(const std::string& flag, const std::string& text) {
  std::istringstream s(text);
  Eigen::Vector3f v;
  char c1 = 0, c2 = 0;
  if (!(s >> v.x() >> c1 >> v.y() >> c2 >> v.z()) || c1 != ',' || c2 != ',' || !v.allFinite()) {
    throw hos::ConfigError(flag, "expected three numbers x,y,z, got '" + text + "'");
  }
  return v;
}

// The oriented points of a PLY; skipped and weightless points are warned of.
hos::PointCloud read_oriented_points(const std::string& path, hos::Reporter& reporter) {
  hos::PlyReadReport read_report;
  hos::PointCloud points = hos::read_point_cloud_ply(path, &read_report);
  if (read_report.num_skipped_nonfinite > 0) {
    reporter.warn(hos::format_message(path, ": skipped ", read_report.num_skipped_nonfinite,
                                      " points with non-finite coordinates"));
  }
  if (read_report.num_invalid_confidence > 0) {
    reporter.warn(hos::format_message(path, ": property 'confidence' is NaN, infinite or negative at ",
                                      read_report.num_invalid_confidence, " points; they weigh nothing"));
  }
  return points;
}

}  // namespace

int main(int argc, char** argv) {
  hos::keep_freed_memory_for_reuse();
  hos::recon::ReconOptions options;
  hos::OptionSet option_set("recon");
  register_options(option_set, options);
  hos::apps::CommonStageFlags flags;
  std::string input_path, output_path, scans_path, view_dir, scanner_pos, report_path, tile_dir, join_dir;
  int tile = -1;
  bool ascii = false;

  CLI::App app{"hos-recon: surface reconstruction with higher-order smoothness (Pan & Skala)"};
  app.add_option("--input", input_path, "oriented points PLY (x y z nx ny nz [confidence])");
  app.add_option("--scans", scans_path, "Stanford .conf of registered range scans (instead of --input)");
  app.add_option("--output", output_path, "output mesh PLY");
  app.add_option("--view-dir", view_dir, "orient all points towards this direction x,y,z");
  app.add_option("--scanner-pos", scanner_pos, "orient every point towards this position x,y,z");
  app.add_flag("--ascii", ascii, "write an ASCII PLY");
  app.add_option("--report", report_path, "also write the stage's figures as JSON (residual per iteration)");
  app.add_option("--tile", tile, "solve only tile K of a tiled run into --tile-dir (no --output)");
  app.add_option("--tile-dir", tile_dir, "folder of the tiles' functions (default: next to --output, removed after)");
  app.add_option("--join-tiles", join_dir, "join the tiles solved into this folder into --output");
  hos::apps::add_common_stage_flags(app, flags, option_set);
  if (const auto code = hos::apps::parse_stage_command_line(app, argc, argv, flags, option_set)) return *code;
  const bool solve_one_tile = tile >= 0;
  if ((input_path.empty() == scans_path.empty()) || output_path.empty() != solve_one_tile ||
      (solve_one_tile && (tile_dir.empty() || !join_dir.empty()))) {
    std::cerr << "hos-recon: error: give exactly one of --input or --scans, and --output, or --tile K with "
                 "--tile-dir DIR (see --help)\n";
    return hos::kExitUsage;
  }

  const auto write_result = [&](const hos::recon::ReconResult& result, hos::Reporter& reporter) {
    hos::write_mesh_ply(output_path, result.mesh, ascii ? hos::PlyFormat::kAscii : hos::PlyFormat::kBinaryLittleEndian);
    if (!report_path.empty()) hos::recon::write_recon_report(report_path, result);
    const auto& s = result.stats;
    reporter.info(hos::format_message("wrote ", output_path, ": ", result.mesh.num_vertices(), " vertices, ",
                                      result.mesh.num_faces(), " faces; grid ", s.grid_dims.x(), "x", s.grid_dims.y(),
                                      "x", s.grid_dims.z(), ", ", s.solver_iterations, " solver iterations, residual ",
                                      s.relative_residual, ", times field ", s.seconds_field, " s, solve ",
                                      s.seconds_solve, " s, mesh ", s.seconds_mesh, " s"));
  };
  return hos::apps::run_stage_main("recon", flags, [&](hos::Reporter& reporter) {
    hos::apps::apply_config_and_overrides(option_set, flags);
    options.validate();
    if (!solve_one_tile) hos::check_writable_target(output_path);  // before the solve, not after
    const std::string source = scans_path.empty() ? input_path : scans_path;
    hos::PointCloud points = scans_path.empty() ? read_oriented_points(input_path, reporter)
                                                : hos::recon::load_stanford_scans(scans_path, reporter);
    if (!view_dir.empty()) hos::recon::orient_by_view_direction(points, parse_vector("--view-dir", view_dir));
    if (!scanner_pos.empty()) {
      hos::recon::orient_by_scanner_position(points, parse_vector("--scanner-pos", scanner_pos));
    }
    hos::recon::check_reconstructable(points, source);
    if (solve_one_tile || !join_dir.empty()) {
      const hos::recon::TiledRun run = hos::recon::prepare_tiled_run(points, options, reporter);
      if (solve_one_tile) {
        hos::recon::solve_tile(run, tile, tile_dir, reporter);
        reporter.info(hos::format_message("wrote ", hos::recon::tile_function_file(tile_dir, tile).string()));
        return;
      }
      write_result(hos::recon::join_tiles(run, points, join_dir, reporter), reporter);
      return;
    }
    const std::filesystem::path tiles_dir = tile_dir.empty() ? output_path + ".tiles" : tile_dir;
    write_result(hos::recon::reconstruct_with_tiles(points, options, tiles_dir, reporter), reporter);
    if (tile_dir.empty()) std::filesystem::remove_all(tiles_dir);
  });
}
