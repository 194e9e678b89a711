// recon/sample_density.*: the grid resolution follows the samples' spacing.
#include "recon/sample_density.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/reporter.h"
#include "recon/memory_budget.h"
#include "recon/reconstruct.h"
#include "synth/shapes.h"

namespace hos::recon {
namespace {

constexpr int kLattice = 400;  // samples per side of the planar lattice
constexpr double kSpacing = 1.0 / kLattice;

// A square lattice of kLattice^2 samples with spacing kSpacing in the plane z = 0.
std::vector<Eigen::Vector3f> planar_lattice() {
  std::vector<Eigen::Vector3f> points;
  points.reserve(kLattice * kLattice);
  for (int y = 0; y < kLattice; ++y) {
    for (int x = 0; x < kLattice; ++x) points.emplace_back(x * kSpacing, y * kSpacing, 0.0f);
  }
  return points;
}

// The domain's longest side: the lattice's extent plus the margin on both sides.
double domain_side(const ReconOptions& o) { return (kLattice - 1) * kSpacing * (1.0 + 2.0 * o.margin); }

TEST(SampleDensity, PlanarLatticeCellsHoldTheSquareOfCellSizeOverSpacing) {
  const std::vector<Eigen::Vector3f> points = planar_lattice();
  const BoundingBox box = bounding_box(points);
  const ReconOptions options;
  for (int resolution : {60, 120, 240}) {
    const double ratio = domain_side(options) / resolution / kSpacing;  // cell size / spacing
    const double mean = mean_samples_per_occupied_cell(box, points, options, resolution);
    EXPECT_NEAR(mean, ratio * ratio, 0.1 * ratio * ratio) << "resolution " << resolution;
  }
}

TEST(SampleDensity, ChosenCellsSpanTheSpacingTimesTheRootOfTheSamplesPerCell) {
  const std::vector<Eigen::Vector3f> points = planar_lattice();
  ReconOptions options;
  for (double per_cell : {4.0, 6.0, 16.0}) {
    options.samples_per_cell = per_cell;
    const double expected = domain_side(options) / (kSpacing * std::sqrt(per_cell));
    const int chosen = resolution_from_density(bounding_box(points), points, options);
    // Within the rule's step of 8 cells and 3% (the lattice's alignment to the cells).
    EXPECT_NEAR(chosen, expected, 8.0 + 0.03 * expected) << per_cell << " samples per cell";
    EXPECT_EQ(chosen % 8, 0);
  }
}

// A facade and, far behind it, a small patch of another surface (a
// building seen through a gap): the domain grows, the cells keep following
// the spacing, here beyond 1100 cells.
TEST(SampleDensity, AFarPatchWidensTheDomainNotTheCells) {
  std::vector<Eigen::Vector3f> points = planar_lattice();
  constexpr int kPatch = 57;       // 2% of the facade's samples
  constexpr double kOffset = 6.0;  // the patch's distance along x
  for (int y = 0; y < kPatch; ++y) {
    for (int x = 0; x < kPatch; ++x) points.emplace_back(kOffset + x * kSpacing, y * kSpacing, 0.0f);
  }
  const ReconOptions options;
  const double side = (kOffset + (kPatch - 1) * kSpacing) * (1.0 + 2.0 * options.margin);
  const double expected = side / (kSpacing * std::sqrt(options.samples_per_cell));
  ASSERT_GT(expected, 1100.0);
  const int chosen = resolution_from_density(bounding_box(points), points, options);
  EXPECT_NEAR(chosen, expected, 8.0 + 0.03 * expected);
}

TEST(SampleDensity, FourTimesTheSamplesOnASurfaceDoubleTheResolution) {
  const std::vector<Eigen::Vector3f> sparse = synth::sample_sphere(160000, 1.0, 0.0, 3).positions;
  const std::vector<Eigen::Vector3f> dense = synth::sample_sphere(640000, 1.0, 0.0, 4).positions;
  const ReconOptions options;
  const int a = resolution_from_density(bounding_box(sparse), sparse, options);
  const int b = resolution_from_density(bounding_box(dense), dense, options);
  EXPECT_GT(a, kMinDensityResolution);
  EXPECT_NEAR(static_cast<double>(b) / a, 2.0, 0.2) << a << " -> " << b;
}

TEST(SampleDensity, ClampsToItsRange) {
  const std::vector<Eigen::Vector3f> few = synth::sample_sphere(500, 1.0, 0.0, 5).positions;
  const std::vector<Eigen::Vector3f> lattice = planar_lattice();
  ReconOptions options;
  EXPECT_EQ(resolution_from_density(bounding_box(few), few, options), kMinDensityResolution);
  options.samples_per_cell = 1.0;  // every grid qualifies
  EXPECT_EQ(resolution_from_density(bounding_box(lattice), lattice, options), kMaxDensityResolution);
}

TEST(SampleDensity, ReconstructionRefinesTheDensitysGridWithinTheMemoryBudget) {
  const PointCloud sphere = synth::sample_sphere(160000, 1.0, 0.0, 6);
  const BoundingBox box = bounding_box(sphere.positions);
  ReconOptions options;  // resolution 0: from the density
  options.density_refinement = 1.5;
  const int from_density = resolution_from_density(box, sphere.positions, options);

  const ReconResult free_run = reconstruct_surface(sphere, options, null_reporter());
  EXPECT_NEAR(free_run.stats.resolution, 1.5 * from_density, 8);
  EXPECT_LT(free_run.stats.samples_per_occupied_cell, options.samples_per_cell);

  // A budget that fits about the density's own grid caps the refinement instead of refusing the run.
  ReconOptions unrefined = options;
  unrefined.resolution = from_density;
  const std::size_t bytes = estimate_peak_bytes(make_domain(box, unrefined), sphere.positions, unrefined);
  options.max_memory_mb = static_cast<int>(bytes / (1024 * 1024)) + 1;
  const ReconResult capped = reconstruct_surface(sphere, options, null_reporter());
  EXPECT_LT(capped.stats.resolution, free_run.stats.resolution - 8);
  EXPECT_GE(capped.stats.resolution, from_density - 8);
  EXPECT_FALSE(capped.mesh.faces.empty());
}

// Trimming must bridge the gaps between samples, a matter of their spacing:
// where the samples are 10x sparser than on average, a twice finer grid keeps
// the surface closed only if the trim distance keeps its length.
TEST(SampleDensity, RefinedGridsTrimNoMoreThanTheDensitysGrid) {
  const PointCloud sphere = synth::sample_sphere(40000, 1.0, 0.0, 8);
  PointCloud uneven;
  for (std::size_t i = 0; i < sphere.size(); ++i) {
    if (sphere.positions[i].z() > 0.0f && i % 10 != 0) continue;  // the upper half 10x sparser
    uneven.positions.push_back(sphere.positions[i]);
    uneven.normals.push_back(sphere.normals[i]);
  }
  ReconOptions options;
  options.density_refinement = 1.0;
  const ReconResult plain = reconstruct_surface(uneven, options, null_reporter());
  options.density_refinement = 2.0;
  const ReconResult refined = reconstruct_surface(uneven, options, null_reporter());
  EXPECT_GT(refined.stats.resolution, plain.stats.resolution + plain.stats.resolution / 2);
  // The trimmed share of the faces, not their count: the finer grid has about 4x the faces.
  const auto trimmed_share = [](const ReconResult& r) {
    return static_cast<double>(r.stats.faces_trimmed) / static_cast<double>(r.stats.faces_before_trim);
  };
  EXPECT_LE(trimmed_share(refined), trimmed_share(plain) + 0.002)
      << refined.stats.faces_trimmed << " of " << refined.stats.faces_before_trim << " against "
      << plain.stats.faces_trimmed << " of " << plain.stats.faces_before_trim;
}

TEST(SampleDensity, ResolutionsBelowTheGridsMinimumOtherThanZeroAreRefused) {
  ReconOptions options;
  options.resolution = 5;
  EXPECT_THROW(options.validate(), ConfigError);
  options.resolution = 0;
  EXPECT_NO_THROW(options.validate());
  options.resolution = kMinResolution;
  EXPECT_NO_THROW(options.validate());
}

}  // namespace
}  // namespace hos::recon
