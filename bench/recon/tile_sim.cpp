// Simulation of tiled reconstruction (docs/scale.md, "Design: tiled
// reconstruction"): the points are cut into 2x2x2 tiles at the median of
// each axis, each tile (extended by an overlap) is reconstructed alone at the
// whole run's voxel size, the tiles' implicit functions are normalised to
// approximate signed distances and blended with partition-of-unity weights,
// and the surface of the blended function is compared with the whole run's:
// separately near the cut planes (the seams) and away from them. A second
// variant switches hard between tiles at the cut planes (no blending).
//   hos-tile-sim --input points.ply [--resolution 256] [--overlap 0.1] [--seam-voxels 3]
// Distances are printed in voxels of the whole run.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "core/ply_io.h"
#include "core/reporter.h"
#include "eval/surface_distance.h"
#include "recon/isosurface.h"
#include "recon/reconstruct.h"
#include "recon/trim.h"

namespace {
using namespace hos;

struct Tile {
  Eigen::Vector3d core_min, core_max;  // +-infinity on the outer sides
  Eigen::Vector3d ext_min, ext_max;    // core extended by the overlap
  std::array<bool, 3> has_lo{}, has_hi{};
  recon::ScalarGrid f;
  double iso = 0.0, scale = 1.0;
  std::size_t points = 0;
  double seconds = 0.0;
};

double smoothstep(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// 1 in the core, falling smoothly to 0 at the extended face on each side
// with a neighbour (the tile's distorted rim never counts).
double blend_weight(const Tile& t, const Eigen::Vector3d& x) {
  double w = 1.0;
  for (int a = 0; a < 3; ++a) {
    if (t.has_lo[a] && x[a] < t.core_min[a]) {
      w *= smoothstep((x[a] - t.ext_min[a]) / (t.core_min[a] - t.ext_min[a]));
    }
    if (t.has_hi[a] && x[a] > t.core_max[a]) {
      w *= smoothstep((t.ext_max[a] - x[a]) / (t.ext_max[a] - t.core_max[a]));
    }
  }
  return w;
}

bool in_core(const Tile& t, const Eigen::Vector3d& x) {
  for (int a = 0; a < 3; ++a) {
    if (x[a] < t.core_min[a] || x[a] >= t.core_max[a]) return false;
  }
  return true;
}

// The tile's function as an approximate signed distance.
double normalised(const Tile& t, const Eigen::Vector3d& x) { return (t.f.sample(x) - t.iso) / t.scale; }

double median(std::vector<double> v) {
  if (v.empty()) return 1.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

TriangleMesh surface_of(const recon::ScalarGrid& g,
                        const PointCloud& points,
                        const recon::ReconOptions& options,
                        double voxel) {
  TriangleMesh mesh = recon::extract_isosurface(g, 0.0);
  recon::trim_far_from_samples(mesh, points.positions, options.trim.distance_voxels * voxel,
                               options.trim.min_component_fraction);
  recon::remove_unreferenced_vertices(mesh);
  return mesh;
}

struct ZoneStats {
  eval::DistanceStats seam, core;
};

// Distances from samples of `from` to `to`, split by the distance of the
// sample to the nearest cut plane (seam: closer than seam_width).
ZoneStats zone_distances(const TriangleMesh& from,
                         const TriangleMesh& to,
                         const Eigen::Vector3d& cut,
                         double seam_width) {
  const auto samples = eval::sample_surface_uniform(from, 200000, 7);
  const auto d = eval::distances_to_mesh(samples, to, null_reporter());
  std::vector<double> seam, core;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    bool near_cut = false;
    for (int a = 0; a < 3; ++a) near_cut |= std::abs(samples[i][a] - cut[a]) < seam_width;
    (near_cut ? seam : core).push_back(d[i]);
  }
  return {eval::summarize_distances(seam), eval::summarize_distances(core)};
}

void print_row(const std::string& variant, const std::string& direction, const ZoneStats& z, double voxel) {
  const auto f = [&](double v) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(3) << v / voxel;
    return s.str();
  };
  std::cout << "| " << variant << " | " << direction << " | " << f(z.seam.mean) << " | " << f(z.seam.p90) << " | "
            << f(z.seam.max) << " | " << f(z.core.mean) << " | " << f(z.core.p90) << " | " << f(z.core.max) << " | "
            << z.seam.count << " / " << z.core.count << " |\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::string input;
  int resolution = 256;
  double overlap_fraction = 0.1;
  double seam_voxels = 3.0;
  CLI::App app{"hos-tile-sim: seam error of tiled reconstruction (2x2x2 tiles, blended implicit functions)"};
  app.add_option("--input", input, "oriented points (PLY)")->required();
  app.add_option("--resolution", resolution, "cells along the longest side of the whole run's domain");
  app.add_option("--overlap", overlap_fraction, "overlap on each side of a cut, as a fraction of the points' extent");
  app.add_option("--seam-voxels", seam_voxels, "samples this close to a cut plane (in voxels) count as seam");
  CLI11_PARSE(app, argc, argv);

  const PointCloud points = read_point_cloud_ply(input);
  recon::ReconOptions options;
  options.resolution = resolution;
  const auto t0 = std::chrono::steady_clock::now();
  const recon::ReconResult whole = recon::reconstruct_surface(points, options, null_reporter());
  const double whole_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double voxel = whole.stats.voxel_size;
  const BoundingBox box = bounding_box(points.positions);
  const Eigen::Vector3d extent = box.extent().cast<double>();
  const Eigen::Vector3d overlap = overlap_fraction * extent;

  // Cut planes at the median of each axis: tiles of similar point counts.
  Eigen::Vector3d cut;
  for (int a = 0; a < 3; ++a) {
    std::vector<double> v;
    for (const auto& p : points.positions) v.push_back(p[a]);
    cut[a] = median(v);
  }
  std::vector<Tile> tiles;
  for (int t = 0; t < 8; ++t) {
    Tile tile;
    for (int a = 0; a < 3; ++a) {
      const bool high = (t >> a) & 1;
      tile.has_lo[a] = high;
      tile.has_hi[a] = !high;
      tile.core_min[a] = high ? cut[a] : -1e30;
      tile.core_max[a] = high ? 1e30 : cut[a];
      tile.ext_min[a] = high ? cut[a] - overlap[a] : -1e30;
      tile.ext_max[a] = high ? 1e30 : cut[a] + overlap[a];
    }
    PointCloud part;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d x = points.positions[i].cast<double>();
      if ((x.array() >= tile.ext_min.array()).all() && (x.array() <= tile.ext_max.array()).all()) {
        part.positions.push_back(points.positions[i]);
        part.normals.push_back(points.normals[i]);
        if (points.has_confidence()) part.confidence.push_back(points.confidence[i]);
      }
    }
    tile.points = part.size();
    // The whole run's voxel and smoothing length: lambda is weighted by
    // (D / 50)^2 with D the domain's longest side (recon_options.h).
    recon::ReconOptions tile_options = options;
    tile_options.voxel_size = voxel;
    const double ratio = double(box.extent().maxCoeff()) / bounding_box(part.positions).extent().maxCoeff();
    tile_options.lambda = options.lambda * ratio * ratio;
    const auto t1 = std::chrono::steady_clock::now();
    recon::ReconResult r = recon::reconstruct_surface(part, tile_options, null_reporter());
    tile.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    tile.f = std::move(r.function);
    tile.iso = r.stats.isovalue;
    std::vector<double> gradients;
    const double h = tile.f.geometry.spacing;
    for (const auto& p : part.positions) {
      const Eigen::Vector3d x = p.cast<double>();
      if (!in_core(tile, x)) continue;
      Eigen::Vector3d g;
      for (int a = 0; a < 3; ++a) {
        const Eigen::Vector3d e = Eigen::Vector3d::Unit(a) * h;
        g[a] = (tile.f.sample(x + e) - tile.f.sample(x - e)) / (2 * h);
      }
      gradients.push_back(g.norm());
    }
    tile.scale = median(gradients);
    std::cerr << "tile " << t << ": " << tile.points << " points, grid " << tile.f.geometry.dims.transpose() << ", "
              << tile.seconds << " s\n";
    tiles.push_back(std::move(tile));
  }

  // The blended and the hard-switched functions on the whole run's grid.
  const recon::GridGeometry& geometry = whole.function.geometry;
  recon::ScalarGrid blended(geometry), switched(geometry);
#pragma omp parallel for schedule(dynamic, 1)
  for (int k = 0; k < geometry.dims.z(); ++k) {
    for (int j = 0; j < geometry.dims.y(); ++j) {
      for (int i = 0; i < geometry.dims.x(); ++i) {
        const Eigen::Vector3d x = geometry.position(i, j, k);
        double sum = 0, weights = 0;
        for (const Tile& t : tiles) {
          if (in_core(t, x)) switched.values[geometry.index(i, j, k)] = normalised(t, x);
          const double w = blend_weight(t, x);
          if (w <= 0) continue;
          sum += w * normalised(t, x);
          weights += w;
        }
        blended.values[geometry.index(i, j, k)] = sum / weights;
      }
    }
  }
  // The whole run's function normalised the same way, so all three surfaces
  // come from the same extraction and trimming.
  recon::ScalarGrid reference(geometry);
  {
    std::vector<double> gradients;
    for (const auto& p : points.positions) {
      const Eigen::Vector3d x = p.cast<double>();
      Eigen::Vector3d g;
      for (int a = 0; a < 3; ++a) {
        const Eigen::Vector3d e = Eigen::Vector3d::Unit(a) * voxel;
        g[a] = (whole.function.sample(x + e) - whole.function.sample(x - e)) / (2 * voxel);
      }
      gradients.push_back(g.norm());
    }
    const double scale = median(gradients);
    for (std::size_t n = 0; n < reference.values.size(); ++n) {
      reference.values[n] = (whole.function.values[n] - whole.stats.isovalue) / scale;
    }
  }
  const TriangleMesh reference_mesh = surface_of(reference, points, options, voxel);
  const TriangleMesh blended_mesh = surface_of(blended, points, options, voxel);
  const TriangleMesh switched_mesh = surface_of(switched, points, options, voxel);

  std::cout << points.size() << " points, whole grid " << geometry.dims.transpose() << " (" << whole_seconds
            << " s), voxel " << voxel << ", diagonal " << box.diagonal() << " (" << box.diagonal() / voxel
            << " voxels), overlap " << overlap_fraction << " of the extent per side (" << overlap.minCoeff() / voxel
            << "-" << overlap.maxCoeff() / voxel << " voxels)\n";
  std::cout << "faces: whole " << reference_mesh.num_faces() << ", blended " << blended_mesh.num_faces()
            << ", switched " << switched_mesh.num_faces() << "\n\n";
  std::cout << "| variant | distance | seam mean | seam p90 | seam max | core mean | core p90 | core max | samples "
               "seam / core |\n|---|---|---|---|---|---|---|---|---|\n";
  print_row("blended", "tiled -> whole", zone_distances(blended_mesh, reference_mesh, cut, seam_voxels * voxel), voxel);
  print_row("blended", "whole -> tiled", zone_distances(reference_mesh, blended_mesh, cut, seam_voxels * voxel), voxel);
  print_row("switched", "tiled -> whole", zone_distances(switched_mesh, reference_mesh, cut, seam_voxels * voxel),
            voxel);
  print_row("switched", "whole -> tiled", zone_distances(reference_mesh, switched_mesh, cut, seam_voxels * voxel),
            voxel);
  return 0;
}
