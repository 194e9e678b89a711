// Tiled reconstruction (recon/tiled_reconstruction.*, recon/tile_plan.*,
// recon/tile_function_file.*) against the whole run on the same points: the
// bounds come from the simulation on the bunny in 8 tiles (docs/scale.md:
// seam and rest mean 0.011 voxel, max 0.7-1.1 voxel at 16 voxels of overlap).
#include "recon/tiled_reconstruction.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>

#include "core/error.h"
#include "core/mesh_connectivity.h"
#include "eval/surface_distance.h"
#include "recon/tile_function_file.h"
#include "synth/shapes.h"
#include "tests/recon/shape_samples.h"
#include "tests/support/test_support.h"

namespace hos::recon {
namespace {

using testing::analyze_topology;

ReconOptions options_at(int resolution, int tiles) {
  ReconOptions o;
  o.resolution = resolution;
  o.tiles = tiles;
  return o;
}

// Distances (in voxels) from samples of `from` to `to`, split at 3 voxels
// from the seams, as the simulation splits them.
eval::ZoneDistances zone_distances(const TiledRun& run, const TriangleMesh& from, const TriangleMesh& to) {
  eval::ZoneDistances z = eval::distances_by_zone(
      from, to, 40000, 7, [&](const Eigen::Vector3f& x) { return voxels_to_seam(run, x) < 3.0; }, null_reporter());
  for (eval::DistanceStats* s : {&z.in_zone, &z.rest}) {
    for (double* v : {&s->mean, &s->median, &s->p90, &s->rms, &s->max}) *v /= run.stats.voxel_size;
  }
  return z;
}

TEST(TilePlan, CoresShareTheirFacesAndCoverTheGrid) {
  const PointCloud points = synth::sample_sphere(20000, 1.0, 0.0, 3);
  for (int tiles : {2, 3, 8}) {
    const TiledRun run = prepare_tiled_run(points, options_at(48, tiles), null_reporter());
    ASSERT_EQ(run.plan.tiles.size(), static_cast<std::size_t>(tiles));
    const GridGeometry& g = run.plan.lattice;
    // Every cell in exactly one core; every node's weights sum to > 0.
    std::int64_t cells = 0;
    for (const Tile& t : run.plan.tiles) {
      cells += std::int64_t{t.core.hi.x() - t.core.lo.x()} * (t.core.hi.y() - t.core.lo.y()) *
               (t.core.hi.z() - t.core.lo.z());
      EXPECT_EQ(t.grid.spacing, g.spacing);
      EXPECT_TRUE(t.grid.can_coarsen(3));
      for (int a = 0; a < 3; ++a) {
        EXPECT_LE(t.grid_offset[a], t.extended.lo[a]);
        EXPECT_GE(t.grid_offset[a] + t.grid.dims[a] - 1, t.extended.hi[a]);
      }
    }
    EXPECT_EQ(cells, std::int64_t{g.dims.x() - 1} * (g.dims.y() - 1) * (g.dims.z() - 1));
    for (int k = 0; k < g.dims.z(); k += 3) {
      for (int j = 0; j < g.dims.y(); j += 3) {
        for (int i = 0; i < g.dims.x(); i += 3) {
          int in_cores = 0;
          double sum = 0.0;
          for (const Tile& t : run.plan.tiles) {
            in_cores += t.core.contains({i, j, k});
            sum += blend_weight(t, {i, j, k}, TileBlend::kSmooth);
          }
          ASSERT_GE(in_cores, 1);
          ASSERT_GE(sum, 1.0) << "a core's own weight is 1";
        }
      }
    }
  }
}

TEST(TilePlan, WeightsAreOneInTheCoreAndFallSmoothlyToZeroAtTheExtendedFace) {
  const PointCloud points = synth::sample_sphere(20000, 1.0, 0.0, 3);
  const TiledRun run = prepare_tiled_run(points, options_at(64, 2), null_reporter());
  const Tile& low = run.plan.tiles[0];
  const int axis = low.neighbour_above[0] ? 0 : (low.neighbour_above[1] ? 1 : 2);
  ASSERT_TRUE(low.neighbour_above[axis]);
  const int cut = low.core.hi[axis], end = low.extended.hi[axis];
  EXPECT_EQ(end - cut, 16) << "the default overlap";
  Eigen::Vector3i n = (low.core.lo + low.core.hi) / 2;
  n[axis] = cut;
  EXPECT_EQ(blend_weight(low, n, TileBlend::kSmooth), 1.0);
  n[axis] = end;
  EXPECT_EQ(blend_weight(low, n, TileBlend::kSmooth), 0.0);
  double previous = 1.0, largest_step = 0.0;
  for (int x = cut + 1; x <= end; ++x) {
    n[axis] = x;
    const double w = blend_weight(low, n, TileBlend::kSmooth);
    EXPECT_LT(w, previous);
    largest_step = std::max(largest_step, previous - w);
    previous = w;
  }
  // C1: the steps are small at both ends (a linear ramp's are all 1/16).
  n[axis] = cut + 1;
  EXPECT_LT(1.0 - blend_weight(low, n, TileBlend::kSmooth), 0.25 / 16);
  n[axis] = end - 1;
  EXPECT_LT(blend_weight(low, n, TileBlend::kSmooth), 0.25 / 16);
  EXPECT_LT(largest_step, 1.6 / 16);
}

TEST(TilePlan, TheMemoryBudgetChoosesTheTiles) {
  const PointCloud points = synth::sample_sphere(20000, 1.0, 0.0, 4);
  ReconOptions o = options_at(128, 0);
  const TiledRun one = prepare_tiled_run(points, o, null_reporter());
  ASSERT_EQ(one.plan.tiles.size(), 1u) << "the whole grid fits the machine";
  const std::size_t whole = one.plan.whole_estimated_peak_bytes;
  o.max_memory_mb = static_cast<int>(whole / (1024 * 1024) / 2);
  const TiledRun tiled = prepare_tiled_run(points, o, null_reporter());
  EXPECT_GT(tiled.plan.tiles.size(), 1u);
  for (const Tile& t : tiled.plan.tiles) {
    EXPECT_LE(t.estimated_peak_bytes, std::size_t(o.max_memory_mb) * 1024 * 1024);
  }
  o.max_memory_mb = 1;  // below any tile's fixed part
  EXPECT_THROW(prepare_tiled_run(points, o, null_reporter()), ConfigError);
}

TEST(TilePlan, TilesAskedForAreHeldToTheBudget) {
  const PointCloud points = synth::sample_sphere(20000, 1.0, 0.0, 4);
  ReconOptions o = options_at(128, 2);
  const TiledRun two = prepare_tiled_run(points, o, null_reporter());
  ASSERT_EQ(two.plan.tiles.size(), 2u);
  std::size_t peak = 0;
  for (const Tile& t : two.plan.tiles) peak = std::max(peak, t.estimated_peak_bytes);
  const int peak_mb = static_cast<int>(peak / (1024 * 1024));
  ASSERT_GT(peak_mb, 2);
  o.max_memory_mb = peak_mb + 1;
  EXPECT_EQ(prepare_tiled_run(points, o, null_reporter()).plan.tiles.size(), 2u);
  o.max_memory_mb = peak_mb - 1;
  EXPECT_THROW(prepare_tiled_run(points, o, null_reporter()), ConfigError);
}

// A sphere with a hole (so there are boundary edges to compare), whole and in
// 2x2x2 tiles with 8 voxels of overlap (the least the simulation advises),
// computed once for the tests below.
class TiledSphere : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const PointCloud sphere = synth::sample_sphere(40000, 1.0, 0.001, 5);
    PointCloud holed;
    for (std::size_t i = 0; i < sphere.size(); ++i) {
      if (sphere.positions[i].normalized().dot(hole()) > 0.95f) continue;
      holed.positions.push_back(sphere.positions[i]);
      holed.normals.push_back(sphere.normals[i]);
    }
    ReconOptions options = options_at(64, 8);
    options.tile_overlap_voxels = 8;
    // Solved tighter than the default, so that the seams' error is not
    // hidden in the solver's (at 1e-3 both are about 0.002 voxel at p90).
    options.solver.tolerance = 1e-5;
    ReconOptions whole = options;
    whole.tiles = 1;
    hos::testing::TempDir dir;
    results_ = new Results{reconstruct_surface(holed, whole, null_reporter()),
                           reconstruct_with_tiles(holed, options, dir.path(), null_reporter()),
                           prepare_tiled_run(holed, options, null_reporter())};
  }
  static void TearDownTestSuite() {
    delete results_;
    results_ = nullptr;
  }
  static Eigen::Vector3f hole() { return Eigen::Vector3f(1, 1, 1).normalized(); }

  struct Results {
    ReconResult whole, tiled;
    TiledRun run;
  };
  static const Results& r() { return *results_; }

 private:
  static inline Results* results_ = nullptr;
};

TEST_F(TiledSphere, MatchesTheWholeRunAtTheSeamsAsElsewhere) {
  ASSERT_EQ(r().run.plan.tiles.size(), 8u);
  for (const auto& [from, to] :
       {std::pair{&r().tiled.mesh, &r().whole.mesh}, std::pair{&r().whole.mesh, &r().tiled.mesh}}) {
    const eval::ZoneDistances z = zone_distances(r().run, *from, *to);
    std::cout << "seam mean " << z.in_zone.mean << " p90 " << z.in_zone.p90 << " max " << z.in_zone.max << " ("
              << z.in_zone.count << "), rest mean " << z.rest.mean << " p90 " << z.rest.p90 << " max " << z.rest.max
              << " (" << z.rest.count << ") voxels\n";
    ASSERT_GT(z.in_zone.count, 1000u);
    // The simulation on the bunny: seam mean 0.011-0.022 voxel at 5-21
    // voxels of overlap, the rest's 0.011-0.014.
    EXPECT_LT(z.in_zone.mean, 0.05);
    EXPECT_LT(z.rest.mean, 0.05);
    // At the seams the surface moves no more than the banded solve may move
    // it (ReconstructSurface.BandedSolveMatchesTheFullSolveNearTheSamples);
    // the rest's maximum is the hole's rim, trimmed a little differently.
    EXPECT_LT(z.in_zone.max, 0.02);
    // Seams no worse than the rest (with 1 voxel of overlap: 0.0029 against 0.0026).
    EXPECT_LE(z.in_zone.p90, z.rest.p90);
  }
}

TEST_F(TiledSphere, SeamsHaveNoCracks) {
  const auto whole = analyze_topology(r().whole.mesh);
  const auto tiled = analyze_topology(r().tiled.mesh);
  std::cout << "boundary edges: whole " << whole.boundary_edges << ", tiled " << tiled.boundary_edges << "\n";
  EXPECT_EQ(tiled.nonmanifold_edges, 0u);
  EXPECT_EQ(tiled.misoriented_edges, 0u);
  EXPECT_EQ(tiled.components, 1);
  EXPECT_GT(whole.boundary_edges, 0u) << "the hole";
  // The hole's rim, trimmed a little differently.
  EXPECT_NEAR(double(tiled.boundary_edges), double(whole.boundary_edges), 0.3 * whole.boundary_edges);
  // Every boundary edge is on that rim, which stays far from the cut planes.
  const TriangleMesh& mesh = r().tiled.mesh;
  const MeshEdges edges = mesh_edges(mesh);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    if (!edges.boundary(e)) continue;
    const FaceSide& side = edges.first_side(e);
    const Eigen::Vector3f mid = 0.5f * (mesh.vertices[side.from(mesh)] + mesh.vertices[side.to(mesh)]);
    EXPECT_GT(mid.normalized().dot(hole()), 0.9f) << "a crack at " << mid.transpose();
  }
}

TEST_F(TiledSphere, HoldsLessGridThanTheWholeRun) {
  const std::int64_t whole = r().whole.function.geometry.num_nodes();
  const ReconStats& s = r().tiled.stats;
  std::cout << "nodes: whole " << whole << ", largest tile " << s.largest_tile_nodes << ", largest core with its ring "
            << s.largest_join_nodes << "\n";
  EXPECT_EQ(s.tiles, 8);
  EXPECT_GT(s.largest_tile_nodes, 0);
  // Each tile's grid is rounded up to coarsen like the whole (dims 16 m - 1):
  // 63^3 here, 71^3 without that.
  EXPECT_LT(s.largest_tile_nodes, 0.6 * whole);
  EXPECT_LT(s.largest_join_nodes, whole / 4);
}

TEST_F(TiledSphere, ReportsEveryTilesSolves) {
  const ReconStats& s = r().tiled.stats;
  // Every tile holds part of the sphere, so each solved at least once.
  ASSERT_GE(s.solve_iterations.size(), 8u);
  int sum = 0;
  for (int iterations : s.solve_iterations) {
    EXPECT_GT(iterations, 0);
    sum += iterations;
  }
  EXPECT_EQ(sum, s.solver_iterations);
  EXPECT_EQ(s.residual_history.size(), static_cast<std::size_t>(sum));
  EXPECT_GT(s.relative_residual, 0.0);
  EXPECT_LE(s.relative_residual, 1e-5);  // the suite's tolerance
}

TEST(TiledReconstruction, BadTileFilesAreInputErrorsNamingTheFile) {
  hos::testing::TempDir dir;
  const PointCloud points = synth::sample_sphere(20000, 1.0, 0.0, 6);
  const ReconOptions options = options_at(40, 2);
  const TiledRun run = prepare_tiled_run(points, options, null_reporter());
  solve_tile(run, 0, dir.path(), null_reporter());
  const auto expect_input_error = [&](const std::filesystem::path& file, const std::string& reason) {
    try {
      join_tiles(run, points, dir.path(), null_reporter());
      ADD_FAILURE() << "no error for " << reason;
    } catch (const InputError& e) {
      EXPECT_EQ(e.path(), file.string()) << reason;
      EXPECT_NE(e.reason().find(reason), std::string::npos) << e.what();
    }
  };
  const auto t1 = tile_function_file(dir.path(), 1);
  expect_input_error(t1, "missing");
  // Tile 1 of a run with another lambda: a foreign file.
  ReconOptions other = options;
  other.lambda = 0.3;
  solve_tile(prepare_tiled_run(points, other, null_reporter()), 1, dir.path(), null_reporter());
  expect_input_error(t1, "does not belong to this run");
  solve_tile(run, 1, dir.path(), null_reporter());
  EXPECT_NO_THROW(join_tiles(run, points, dir.path(), null_reporter()));
  std::filesystem::resize_file(t1, std::filesystem::file_size(t1) - 4);
  expect_input_error(t1, "truncated");
  std::ofstream(t1, std::ios::binary) << "HOSTVIEW and more";
  expect_input_error(t1, "not a hos-recon tile function file");
  EXPECT_THROW(solve_tile(run, 2, dir.path(), null_reporter()), ConfigError);
}

// The joined tiles keep a small piece that confident samples support, as the
// whole solve does (a hanging object), and drop it when few views agreed on
// its samples.
TEST(TiledReconstruction, JoinedTilesKeepSmallPiecesConfidentSamplesSupport) {
  const auto pieces_kept = [](float speck_views) {
    PointCloud points = synth::sample_sphere(15000, 1.0, 0.002, 1);
    points.confidence.assign(points.positions.size(), 9.0f);
    const PointCloud speck = synth::sample_sphere(600, 0.09, 0.002, 2);
    for (std::size_t i = 0; i < speck.positions.size(); ++i) {
      points.positions.push_back(speck.positions[i] + Eigen::Vector3f(1.6f, 0.0f, 0.0f));
      points.normals.push_back(speck.normals[i]);
      points.confidence.push_back(speck_views);
    }
    hos::testing::TempDir dir;
    const ReconResult r = reconstruct_with_tiles(points, options_at(64, 2), dir.path(), null_reporter());
    EXPECT_EQ(r.stats.tiles, 2);
    return std::pair{analyze_topology(r.mesh).components, r.stats.debris.components_kept_by_support};
  };
  EXPECT_EQ(pieces_kept(6.0f), std::pair(2, std::size_t{1}));
  EXPECT_EQ(pieces_kept(2.0f), std::pair(1, std::size_t{0}));
}

}  // namespace
}  // namespace hos::recon
