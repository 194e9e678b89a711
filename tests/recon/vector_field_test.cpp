// recon/vector_field.*: the right-hand side evaluated plane by plane against
// the materialised field (splat and divergence basics are in grid_test.cpp).
#include "recon/vector_field.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "synth/shapes.h"
#include "tests/recon/shape_samples.h"

namespace hos::recon {
namespace {

constexpr int kDensityPasses = 3, kFilterPasses = 3;
// The fused path keeps the fine density in single precision (the
// materialised one in double): agreement to float rounding. A window off by
// one plane gave relative errors of 0.26-0.89.
constexpr double kFusedTolerance = 1e-5;

// -div F of density_scaled_field after normalize_field: the path that
// density_scaled_rhs must reproduce without the field.
std::vector<double> materialised_rhs(const GridGeometry& g,
                                     const std::vector<Eigen::Vector3f>& points,
                                     const std::vector<Eigen::Vector3f>& normals,
                                     const std::vector<float>& weights,
                                     int direction_passes) {
  VectorGrid field = density_scaled_field(g, points, normals, weights, kDensityPasses, direction_passes);
  normalize_field(field, points, kFilterPasses);
  std::vector<double> rhs = divergence(field).values;
  for (double& v : rhs) v = -v;
  return rhs;
}

// Max |a - b| relative to max |b| (b must not be all zero).
double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double diff = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(b[i]));
  }
  EXPECT_GT(scale, 0.0);
  return diff / scale;
}

// Dims that differ per axis (a swapped axis or stride shows) with more than
// 2^17 nodes, so that the planes are split into blocks over threads.
GridGeometry test_grid() {
  GridGeometry g;
  g.dims = Eigen::Vector3i(55, 51, 63);
  g.spacing = 0.1;
  g.origin = Eigen::Vector3d(-2.7, -2.5, -3.1);
  return g;
}

TEST(VectorField, RhsEqualsMaterialisedFieldForRandomOrientedPoints) {
  const GridGeometry g = test_grid();
  std::mt19937 rng(7);
  std::normal_distribution<float> normal;
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<Eigen::Vector3f> points, normals;
  std::vector<float> weights;
  const Eigen::Vector3d extent = g.spacing * (g.dims.cast<double>().array() - 1.0).matrix();
  for (int p = 0; p < 3000; ++p) {
    // Clusters of points with similar normals (a coherent field) mixed with
    // scattered ones of any direction (cancelling orientations); a few
    // points lie beyond the grid's faces.
    const Eigen::Vector3d u(unit(rng), unit(rng), unit(rng));
    const Eigen::Vector3d x = g.origin + ((1.04 * u.array() - 0.02) * extent.array()).matrix();
    Eigen::Vector3f n(normal(rng), normal(rng), normal(rng));
    if (p % 2 == 0) n = Eigen::Vector3f(1.0f, 0.5f, -0.3f) + 0.3f * n;
    points.push_back(x.cast<float>());
    normals.push_back(n.normalized());
    weights.push_back(0.2f + unit(rng));
  }
  for (int direction_passes : {12, 8}) {
    const ScalarGrid rhs =
        density_scaled_rhs(g, points, normals, weights, {kDensityPasses, direction_passes, kFilterPasses});
    EXPECT_LT(relative_difference(rhs.values, materialised_rhs(g, points, normals, weights, direction_passes)),
              kFusedTolerance)
        << direction_passes;
  }
  // Without weights, and on the fine-grid fallback (passes not a multiple of 4).
  for (int direction_passes : {12, 3}) {
    const ScalarGrid rhs =
        density_scaled_rhs(g, points, normals, {}, {kDensityPasses, direction_passes, kFilterPasses});
    EXPECT_LT(relative_difference(rhs.values, materialised_rhs(g, points, normals, {}, direction_passes)),
              direction_passes % 4 == 0 ? kFusedTolerance : 1e-9)
        << direction_passes;
  }
}

TEST(VectorField, RhsEqualsMaterialisedFieldForSphereScannedFromSixDirections) {
  const GridGeometry g = test_grid();
  PointCloud sphere = synth::sample_sphere(20000, 2.2, 0.01, 3);
  synth::coarsen_to_axis_directions(sphere);
  // Shift the centre off the grid's centre so no symmetry hides an axis error.
  for (auto& p : sphere.positions) p += Eigen::Vector3f(-0.1f, 0.15f, -0.05f);
  const ScalarGrid rhs =
      density_scaled_rhs(g, sphere.positions, sphere.normals, {}, {kDensityPasses, 12, kFilterPasses});
  EXPECT_LT(relative_difference(rhs.values, materialised_rhs(g, sphere.positions, sphere.normals, {}, 12)),
            kFusedTolerance);
  // The flux points outwards: the rhs (-div F) is negative inside the shell
  // near the surface and positive outside, so it is not trivially zero.
  const Eigen::Vector3d centre(-0.1, 0.15, -0.05);
  const auto at = [&](const Eigen::Vector3d& x) { return rhs.sample(x); };
  EXPECT_LT(at(centre + Eigen::Vector3d(2.2 - 0.25, 0, 0)), 0.0);
  EXPECT_GT(at(centre + Eigen::Vector3d(2.2 + 0.25, 0, 0)), 0.0);
}

TEST(VectorField, RhsNearTheSamplesEqualsTheWholeGridsAndHoldsEveryNonzeroValue) {
  // test_grid's extent at a third of its spacing: the band leaves out most nodes.
  GridGeometry g;
  g.dims = Eigen::Vector3i(159, 151, 183);
  g.spacing = 0.1 / 3.0;
  g.origin = Eigen::Vector3d(-2.7, -2.5, -3.1);
  PointCloud sphere = synth::sample_sphere(20000, 2.2, 0.01, 3);
  synth::coarsen_to_axis_directions(sphere);
  for (auto& p : sphere.positions) p += Eigen::Vector3f(-0.1f, 0.15f, -0.05f);
  std::vector<float> weights(sphere.size());
  for (std::size_t p = 0; p < weights.size(); ++p) weights[p] = 0.5f + 0.5f * static_cast<float>(p % 7) / 7.0f;
  const ScalarGrid dense =
      density_scaled_rhs(g, sphere.positions, sphere.normals, weights, {kDensityPasses, 12, kFilterPasses});
  const StoredField near = density_scaled_rhs_near_samples(g, sphere.positions, sphere.normals, weights,
                                                           {kDensityPasses, 12, kFilterPasses});
  ASSERT_FALSE(near.nodes->is_all());
  ASSERT_LT(near.nodes->storage_size(), g.num_nodes() / 2);
  // Every node: the stored value, or zero where the layout stores none.
  std::int64_t nonzero = 0, stored = 0;
  double max_abs = 0.0, max_diff = 0.0;
  for (int k = 0; k < g.dims.z(); ++k) {
    for (int j = 0; j < g.dims.y(); ++j) {
      for (int i = 0; i < g.dims.x(); ++i) {
        const double want = dense.values[g.index(i, j, k)];
        const std::int64_t base = near.nodes->row_base(j, k, i);
        const double got = base == ActiveNodes::kNotStored ? 0.0 : near.values[base + i];
        stored += base != ActiveNodes::kNotStored;
        nonzero += want != 0.0;
        max_abs = std::max(max_abs, std::abs(want));
        max_diff = std::max(max_diff, std::abs(got - want));
      }
    }
  }
  EXPECT_EQ(stored, near.nodes->storage_size());
  EXPECT_GT(nonzero, 1000);
  // The same arithmetic in the same order: equal to the last bit.
  EXPECT_EQ(max_diff, 0.0) << "largest |rhs| " << max_abs;
}

}  // namespace
}  // namespace hos::recon
