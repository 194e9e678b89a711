#include "eval/surface_distance.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "synth/shapes.h"
#include "tests/eval/test_meshes.h"

namespace hos::eval {
namespace {

SurfaceDistanceOptions small_options() {
  SurfaceDistanceOptions o;
  o.num_samples = 20000;
  return o;
}

TEST(SampleSurface, UniformByAreaAndDeterministic) {
  // Cube [0,1]^3 with one side subdivided more finely does not bias sampling:
  // each side gets 1/6 of the samples (binomial sigma ~0.0026 at 20000).
  const TriangleMesh mesh = testing::cube(1.0f, Eigen::Vector3f::Zero(), 3);
  const auto samples = sample_surface_uniform(mesh, 20000, 5);
  int on_top = 0;
  for (const auto& p : samples) on_top += std::abs(p.z() - 1.0f) < 1e-6f;
  EXPECT_NEAR(on_top / 20000.0, 1.0 / 6.0, 0.015);
  EXPECT_EQ(samples, sample_surface_uniform(mesh, 20000, 5));
  EXPECT_NE(samples, sample_surface_uniform(mesh, 20000, 6));
}

TEST(CompareSurfaces, ConcentricSpheresGiveRadiusDifference) {
  const TriangleMesh inner = synth::icosphere(5, 1.0);
  const TriangleMesh outer = synth::icosphere(5, 1.01);
  const SurfaceComparison c = compare_surfaces(inner, outer, small_options(), null_reporter());
  // Same tessellation scaled: every distance is 0.01 up to the chord sag of a
  // level-5 icosphere (< 4e-4 of the radius).
  EXPECT_NEAR(c.accuracy.mean, 0.01, 5e-4);
  EXPECT_NEAR(c.accuracy.median, 0.01, 5e-4);
  EXPECT_NEAR(c.completeness.mean, 0.01, 5e-4);
  EXPECT_NEAR(c.chamfer, 0.01, 5e-4);
  // 0.01 is 0.29% of the diagonal 2.02*sqrt(3): P = R = 1 at 0.5%.
  EXPECT_DOUBLE_EQ(c.scores[0].f_score, 1.0);
}

TEST(CompareSurfaces, MeshAgainstItselfHasFScoreOne) {
  const TriangleMesh mesh = synth::icosphere(3, 2.0);
  const SurfaceComparison c = compare_surfaces(mesh, mesh, small_options(), null_reporter());
  ASSERT_EQ(c.scores.size(), 3u);
  for (const auto& s : c.scores) {
    EXPECT_DOUBLE_EQ(s.precision, 1.0);
    EXPECT_DOUBLE_EQ(s.recall, 1.0);
    EXPECT_DOUBLE_EQ(s.f_score, 1.0);
  }
  EXPECT_LT(c.accuracy.max, 1e-6);
  EXPECT_DOUBLE_EQ(c.primary().fraction, 0.01);
}

TEST(CompareSurfaces, TranslatedCubeGivesTheTranslation) {
  const float t = 0.02f;
  const TriangleMesh truth = testing::cube(1.0f, Eigen::Vector3f::Zero());
  const TriangleMesh moved = testing::cube(1.0f, Eigen::Vector3f(t, 0, 0));
  const SurfaceComparison c = compare_surfaces(moved, truth, small_options(), null_reporter());
  // The two x faces are t away, the other four lie on the truth except a
  // strip of width t: max = t, mean = t/3 + O(t^2), p90 = t.
  EXPECT_NEAR(c.accuracy.max, t, 1e-6);
  EXPECT_NEAR(c.accuracy.p90, t, 1e-6);
  EXPECT_NEAR(c.accuracy.mean, t / 3.0, 0.05 * t);
  EXPECT_NEAR(c.completeness.max, t, 1e-6);
}

TEST(CompareSurfaces, PointResultUsesPointsAsIs) {
  const TriangleMesh truth = synth::icosphere(4, 1.0);
  TriangleMesh points;
  points.vertices = sample_surface_uniform(synth::icosphere(4, 1.05), 50000, 3);
  const SurfaceComparison c = compare_surfaces(points, truth, small_options(), null_reporter());
  EXPECT_TRUE(c.result_is_points);
  EXPECT_EQ(c.accuracy.count, 50000u);
  EXPECT_NEAR(c.accuracy.mean, 0.05, 2e-3);
  // Completeness to a point set: at least the radial gap, plus the spacing.
  EXPECT_GT(c.completeness.mean, 0.049);
  EXPECT_LT(c.completeness.mean, 0.06);
}

TEST(CompareSurfaces, OptionsAreValidated) {
  SurfaceDistanceOptions o;
  o.thresholds = {0.01, -1.0};
  EXPECT_THROW(o.validate(), ConfigError);
  o.thresholds = {};
  EXPECT_THROW(o.validate(), ConfigError);
  TriangleMesh empty;
  EXPECT_THROW(compare_surfaces(synth::icosphere(1, 1.0), empty, small_options(), null_reporter()), NumericalError);
}

TEST(SummarizeDistances, NearestRankPercentiles) {
  std::vector<double> d;
  for (int i = 1; i <= 10; ++i) d.push_back(i);
  const DistanceStats s = summarize_distances(d);
  EXPECT_DOUBLE_EQ(s.mean, 5.5);
  EXPECT_DOUBLE_EQ(s.median, 5.0);
  EXPECT_DOUBLE_EQ(s.p90, 9.0);
  EXPECT_DOUBLE_EQ(s.max, 10.0);
  EXPECT_THROW(summarize_distances({1.0, std::nan("")}), NumericalError);
}

}  // namespace
}  // namespace hos::eval
