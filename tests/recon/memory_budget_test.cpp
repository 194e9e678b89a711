#include "recon/memory_budget.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cmath>

#include "core/error.h"
#include "core/reporter.h"
#include "recon/active_nodes.h"
#include "recon/reconstruct.h"
#include "synth/shapes.h"
#include "tests/recon/shape_samples.h"

namespace hos::recon {
namespace {

BoundingBox unit_box() {
  BoundingBox box;
  box.extend(Eigen::Vector3f(-1, -1, -1));
  box.extend(Eigen::Vector3f(1, 1, 1));
  return box;
}

// 100 k samples on the unit sphere, whose bounding box is about unit_box().
std::vector<Eigen::Vector3f> sphere_points() { return synth::sample_sphere(100000, 1.0, 0.0, 7).positions; }

std::size_t estimate_at(int resolution, const ReconOptions& base, const std::vector<Eigen::Vector3f>& points) {
  ReconOptions options = base;
  options.resolution = resolution;
  return estimate_peak_bytes(make_domain(unit_box(), options), points, options);
}

// The bounds must hold every node the band makes active or stores, and be close enough to be
// useful (the estimate's band term is this bound times its bytes per node).
TEST(MemoryBudget, BandBoundCoversTheStoredBand) {
  const std::vector<Eigen::Vector3f> sphere = sphere_points();
  std::vector<Eigen::Vector3f> scattered;  // a few far-apart samples: a band of isolated boxes
  scattered.reserve(40);
  for (int i = 0; i < 40; ++i) {
    scattered.emplace_back(std::sin(1.7f * i), std::cos(2.3f * i), std::sin(0.9f * i + 0.5f));
  }
  const std::vector<const std::vector<Eigen::Vector3f>*> sets = {&sphere, &scattered};
  for (const std::vector<Eigen::Vector3f>* points : sets) {
    for (int resolution : {24, 64, 100}) {
      for (int voxels : {0, 1, 6, 9}) {
        ReconOptions options;
        options.resolution = resolution;
        const GridGeometry grid = make_domain(unit_box(), options);
        const ActiveNodes band = band_around_samples(grid, *points, voxels);
        const std::int64_t stored = band.storage_size();
        const std::int64_t bound = band_stored_nodes_bound(grid, *points, voxels);
        EXPECT_GE(bound, stored) << "resolution " << resolution << ", " << voxels << " voxels";
        EXPECT_LE(bound, grid.num_nodes());
        const std::int64_t active_bound = band_active_nodes_bound(grid, *points, voxels);
        EXPECT_GE(active_bound, band.count()) << "resolution " << resolution << ", " << voxels << " voxels";
        EXPECT_LE(active_bound, bound);
        if (points == &sphere && resolution == 100 && voxels == 6) {
          EXPECT_LE(bound, 1.5 * static_cast<double>(stored));  // measured 1.34x at grids of 64 to 384
        }
      }
    }
  }
}

TEST(MemoryBudget, EstimateGrowsWithTheGrid) {
  const std::vector<Eigen::Vector3f> points = sphere_points();
  ReconOptions options;
  EXPECT_LT(estimate_at(64, options, points), estimate_at(128, options, points));
  // The grid-sized arrays dominate: doubling the resolution multiplies the
  // whole-grid estimate by about 8; keeping only the band, the estimate
  // grows with the surface (about 4x).
  ReconOptions band_only = options;
  band_only.solver.band_storage_above_mnodes = 0;
  const double banded = static_cast<double>(estimate_at(512, band_only, points)) /
                        static_cast<double>(estimate_at(256, band_only, points));
  options.solver.band_voxels = 0;
  const double whole =
      static_cast<double>(estimate_at(512, options, points)) / static_cast<double>(estimate_at(256, options, points));
  EXPECT_GT(whole, 7.0);
  EXPECT_LT(whole, 8.5);
  EXPECT_GT(banded, 3.0);  // the surface's 4x, less the fixed terms
  EXPECT_LT(banded, 5.0);
  // The band's estimate is well below the whole grid's at a large grid.
  EXPECT_LT(2 * estimate_at(512, ReconOptions{}, points), estimate_at(512, options, points));
}

TEST(MemoryBudget, RefusesWithTheLargestResolutionThatFits) {
  ReconOptions options;
  options.resolution = 1024;
  options.max_memory_mb = 512;
  const std::vector<Eigen::Vector3f> points = sphere_points();
  const std::size_t budget = memory_budget_bytes(options);
  ASSERT_EQ(budget, std::size_t{512} << 20);
  const int fitting = largest_resolution_within(unit_box(), points, options, budget);
  ASSERT_GT(fitting, 8);
  EXPECT_LE(estimate_at(fitting, options, points), budget);
  EXPECT_GT(estimate_at(fitting + 1, options, points), budget);
  try {
    check_memory_budget(unit_box(), points, options);
    FAIL() << "a 1024 grid within 512 MB was accepted";
  } catch (const ConfigError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("recon.resolution"), std::string::npos) << message;
    EXPECT_NE(message.find("largest resolution that fits is " + std::to_string(fitting)), std::string::npos) << message;
  }
  options.resolution = fitting;
  EXPECT_NO_THROW(check_memory_budget(unit_box(), points, options));
}

TEST(MemoryBudget, ReconstructRefusesBeforeAllocating) {
  ReconOptions options;
  options.resolution = 2048;  // about 8.6 G nodes: far beyond any budget below
  options.max_memory_mb = 256;
  const PointCloud points = synth::sample_sphere(2000, 1.0, 0.0, 3);
  Reporter reporter;
  EXPECT_THROW(reconstruct_surface(points, options, reporter), ConfigError);
}

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define HOS_HAS_ADDRESS_SANITIZER 1
#endif
#endif
#ifndef HOS_HAS_ADDRESS_SANITIZER
#define HOS_HAS_ADDRESS_SANITIZER 0
#endif

long peak_rss_kb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

// The estimate must not be below what a run really takes. ctest runs each
// test in its own process, so the growth of the peak resident size is this
// run's (the process's own size before it depends on the libraries the test
// binary loads, not on the run).
// band_voxels = 0 solves the whole grid; otherwise the band is used.
void expect_estimate_covers_a_run(int resolution, int band_voxels, bool band_only = false) {
#if defined(__SANITIZE_ADDRESS__) || HOS_HAS_ADDRESS_SANITIZER
  // AddressSanitizer's shadow memory and quarantine add to the resident size
  // (2-4x here): the estimate models the uninstrumented build.
  GTEST_SKIP() << "peak memory is not comparable under AddressSanitizer";
#endif
  ReconOptions options;
  options.resolution = resolution;
  options.solver.band_voxels = band_voxels;
  if (band_only) options.solver.band_storage_above_mnodes = 0;
  const PointCloud points = synth::sample_sphere(50000, 1.0, 0.002, 5);
  const long before_kb = peak_rss_kb();
  Reporter reporter;
  const ReconResult result = reconstruct_surface(points, options, reporter);
  const double measured = 1024.0 * static_cast<double>(peak_rss_kb() - before_kb);
  const BoundingBox box = bounding_box(points.positions);
  const GridGeometry grid = make_domain(box, options);
  const double estimate = static_cast<double>(estimate_peak_bytes(grid, points.positions, options));
  // The run and the estimate take the path this case is for: with a band, the
  // active bound is within half of the grid, so the banded model alone is used.
  EXPECT_EQ(result.stats.band_nodes > 0, band_voxels > 0);
  EXPECT_EQ(keeps_only_band(grid, options), band_only);
  if (band_voxels > 0) {
    EXPECT_LE(2 * band_active_nodes_bound(grid, points.positions, band_voxels), grid.num_nodes());
  }
  EXPECT_GE(estimate, measured) << "estimate " << estimate / 1048576.0 << " MB, the run's peak RSS "
                                << measured / 1048576.0 << " MB over " << before_kb / 1024.0 << " MB before it";
  // ...and not wildly above it (it would refuse grids that fit).
  EXPECT_LE(estimate, 3.0 * measured) << "the run's peak RSS " << measured / 1048576.0 << " MB, estimate "
                                      << estimate / 1048576.0 << " MB";
  EXPECT_GT(result.mesh.num_faces(), 0u);
}

TEST(MemoryBudget, EstimateCoversAMeasuredBandedRun) { expect_estimate_covers_a_run(128, 6); }

TEST(MemoryBudget, EstimateCoversAMeasuredBandOnlyRun) { expect_estimate_covers_a_run(256, 6, true); }

TEST(MemoryBudget, EstimateCoversAMeasuredWholeGridRun) { expect_estimate_covers_a_run(96, 0); }

}  // namespace
}  // namespace hos::recon
