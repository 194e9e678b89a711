// Seam error of tiled reconstruction (docs/scale.md, "Design: tiled
// reconstruction"): the points are reconstructed whole and in tiles
// (recon/tiled_reconstruction.h, both blends: smooth weights across the
// overlaps and a hard switch at the cores' faces), and each tiled surface is
// compared with the whole run's in both directions, separately near the faces
// between cores (the seams) and away from them.
//   hos-tile-sim --input points.ply [--resolution 256] [--tiles 8] [--overlap-voxels 16] [--seam-voxels 3]
// Distances are printed in voxels of the whole run.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "core/ply_io.h"
#include "core/reporter.h"
#include "core/stopwatch.h"
#include "eval/surface_distance.h"
#include "recon/reconstruct.h"
#include "recon/tiled_reconstruction.h"

namespace {
using namespace hos;

void print_row(const std::string& variant, const std::string& direction, const eval::ZoneDistances& z, double voxel) {
  const auto f = [&](double v) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(3) << v / voxel;
    return s.str();
  };
  std::cout << "| " << variant << " | " << direction << " | " << f(z.in_zone.mean) << " | " << f(z.in_zone.p90) << " | "
            << f(z.in_zone.max) << " | " << f(z.rest.mean) << " | " << f(z.rest.p90) << " | " << f(z.rest.max) << " | "
            << z.in_zone.count << " / " << z.rest.count << " |\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::string input;
  recon::ReconOptions options;
  options.resolution = 256;
  options.tiles = 8;
  double seam_voxels = 3.0;
  CLI::App app{"hos-tile-sim: seam error of tiled reconstruction against the whole run"};
  app.add_option("--input", input, "oriented points (PLY)")->required();
  app.add_option("--resolution", options.resolution, "cells along the longest side of the whole run's domain");
  app.add_option("--tiles", options.tiles, "tiles (recon.tiles)");
  app.add_option("--overlap-voxels", options.tile_overlap_voxels, "recon.tile_overlap_voxels");
  app.add_option("--seam-voxels", seam_voxels, "samples this close to a face between cores (voxels) count as seam");
  CLI11_PARSE(app, argc, argv);

  const PointCloud points = read_point_cloud_ply(input);
  recon::ReconOptions whole_options = options;
  whole_options.tiles = 1;
  auto t0 = Clock::now();
  const recon::ReconResult whole = recon::reconstruct_surface(points, whole_options, null_reporter());
  const double whole_seconds = seconds_since(t0);
  const double voxel = whole.stats.voxel_size;
  const BoundingBox box = bounding_box(points.positions);
  std::cout << points.size() << " points, whole grid " << whole.stats.grid_dims.transpose() << " ("
            << whole.function.geometry.num_nodes() << " nodes, " << whole_seconds << " s), voxel " << voxel
            << ", diagonal " << box.diagonal() / voxel << " voxels; " << options.tiles << " tiles, overlap "
            << options.tile_overlap_voxels << " voxels per side\n";

  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("hos-tile-sim-" + std::to_string(::getpid()));
  std::ostringstream table;
  std::cout << "\n| variant | distance | seam mean | seam p90 | seam max | rest mean | rest p90 | rest max | samples "
               "seam / rest |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& [name, blend] :
       {std::pair{"blended", recon::TileBlend::kSmooth}, std::pair{"switched", recon::TileBlend::kSwitch}}) {
    recon::ReconOptions tiled_options = options;
    tiled_options.tile_blend = blend;
    t0 = Clock::now();
    const recon::ReconResult tiled = recon::reconstruct_with_tiles(points, tiled_options, dir, null_reporter());
    const double tiled_seconds = seconds_since(t0);
    std::filesystem::remove_all(dir);
    const recon::TiledRun run = recon::prepare_tiled_run(points, tiled_options, null_reporter());
    const auto near_seam = [&](const Eigen::Vector3f& x) { return recon::voxels_to_seam(run, x) < seam_voxels; };
    print_row(name, "tiled -> whole",
              eval::distances_by_zone(tiled.mesh, whole.mesh, 200000, 7, near_seam, null_reporter()), voxel);
    print_row(name, "whole -> tiled",
              eval::distances_by_zone(whole.mesh, tiled.mesh, 200000, 7, near_seam, null_reporter()), voxel);
    table << name << ": " << tiled_seconds << " s (solver " << tiled.stats.seconds_field + tiled.stats.seconds_solve
          << " s), faces " << tiled.mesh.num_faces() << " (whole " << whole.mesh.num_faces() << "), largest tile grid "
          << tiled.stats.largest_tile_nodes << " nodes, largest core with its ring " << tiled.stats.largest_join_nodes
          << " nodes\n";
  }
  std::cout << "\n" << table.str();
  return 0;
}
