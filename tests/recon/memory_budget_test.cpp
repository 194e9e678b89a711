#include "recon/memory_budget.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include "core/error.h"
#include "core/reporter.h"
#include "recon/reconstruct.h"
#include "tests/recon/shape_samples.h"

namespace hos::recon {
namespace {

BoundingBox unit_box() {
  BoundingBox box;
  box.extend(Eigen::Vector3f(-1, -1, -1));
  box.extend(Eigen::Vector3f(1, 1, 1));
  return box;
}

std::size_t estimate_at(int resolution, const ReconOptions& base) {
  ReconOptions options = base;
  options.resolution = resolution;
  return estimate_peak_bytes(make_domain(unit_box(), options), 100000, options);
}

TEST(MemoryBudget, EstimateGrowsWithTheGrid) {
  const ReconOptions options;
  EXPECT_LT(estimate_at(64, options), estimate_at(128, options));
  // The grid term dominates: doubling the resolution multiplies it by about 8.
  const double ratio = static_cast<double>(estimate_at(512, options)) / static_cast<double>(estimate_at(256, options));
  EXPECT_GT(ratio, 6.0);
  EXPECT_LT(ratio, 9.0);
}

TEST(MemoryBudget, RefusesWithTheLargestResolutionThatFits) {
  ReconOptions options;
  options.resolution = 1024;
  options.max_memory_mb = 512;
  const std::size_t budget = memory_budget_bytes(options);
  ASSERT_EQ(budget, std::size_t{512} << 20);
  const int fitting = largest_resolution_within(unit_box(), 100000, options, budget);
  ASSERT_GT(fitting, 8);
  EXPECT_LE(estimate_at(fitting, options), budget);
  EXPECT_GT(estimate_at(fitting + 1, options), budget);
  try {
    check_memory_budget(unit_box(), 100000, options);
    FAIL() << "a 1024 grid within 512 MB was accepted";
  } catch (const ConfigError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("recon.resolution"), std::string::npos) << message;
    EXPECT_NE(message.find("largest resolution that fits is " + std::to_string(fitting)), std::string::npos)
        << message;
  }
  options.resolution = fitting;
  EXPECT_NO_THROW(check_memory_budget(unit_box(), 100000, options));
}

TEST(MemoryBudget, ReconstructRefusesBeforeAllocating) {
  ReconOptions options;
  options.resolution = 2048;  // about 8.6 G nodes: far beyond any budget below
  options.max_memory_mb = 256;
  const PointCloud points = testing::sample_sphere(2000, 1.0, 0.0, 3);
  Reporter reporter;
  EXPECT_THROW(reconstruct_surface(points, options, reporter), ConfigError);
}

long peak_rss_kb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

// The estimate must not be below what a run really takes. ctest runs each
// test in its own process, so the peak resident size grows from this run.
TEST(MemoryBudget, EstimateCoversAMeasuredRun) {
  ReconOptions options;
  options.resolution = 96;
  const PointCloud points = testing::sample_sphere(50000, 1.0, 0.002, 5);
  const long before_kb = peak_rss_kb();
  Reporter reporter;
  const ReconResult result = reconstruct_surface(points, options, reporter);
  const double measured = 1024.0 * static_cast<double>(peak_rss_kb());
  const BoundingBox box = bounding_box(points.positions);
  const double estimate = static_cast<double>(estimate_peak_bytes(make_domain(box, options), points.size(), options));
  EXPECT_GE(estimate, measured) << "peak RSS " << measured / 1048576.0 << " MB, before the run "
                                << before_kb / 1024.0 << " MB";
  // ...and not wildly above it (it would refuse grids that fit).
  EXPECT_LE(estimate, 3.0 * measured);
  EXPECT_GT(result.mesh.num_faces(), 0u);
}

}  // namespace
}  // namespace hos::recon
