// recon/sample_frame.*: the reconstruction is independent of the input's
// scale and position, refuses clouds without extent, drops far outliers and
// copes with absurd normal lengths and unusable confidences (issue #14,
// items 5, 7, 8 and 9).

#include "recon/sample_frame.h"  // IWYU: the unit under test, used through reconstruct_surface

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "recon/reconstruct.h"
#include "synth/shapes.h"
#include "tests/recon/shape_samples.h"
#include "tests/support/message_log.h"
#include "tests/support/test_support.h"

namespace hos::recon {
namespace {

using ::testing::HasSubstr;

ReconOptions small_options() {
  ReconOptions o;
  o.resolution = 32;
  return o;
}

// Mean and largest |distance to the centre - radius| / radius of the vertices.
std::pair<double, double> relative_radial_error(const TriangleMesh& mesh,
                                                const Eigen::Vector3d& center,
                                                double radius) {
  double mean = 0.0, worst = 0.0;
  for (const auto& v : mesh.vertices) {
    const double e = std::abs((v.cast<double>() - center).norm() - radius) / radius;
    mean += e;
    worst = std::max(worst, e);
  }
  return {mean / static_cast<double>(std::max<std::size_t>(mesh.num_vertices(), 1)), worst};
}

PointCloud scaled(PointCloud points, double scale, const Eigen::Vector3d& offset) {
  for (auto& p : points.positions) p = (p.cast<double>() * scale + offset).cast<float>();
  return points;
}

TEST(SampleFrame, IdenticalPointsAreBadInput) {
  PointCloud points;
  for (int i = 0; i < 100; ++i) {
    points.positions.emplace_back(1.0f, 2.0f, 3.0f);
    points.normals.emplace_back(0.0f, 0.0f, 1.0f);
  }
  EXPECT_THROW(check_reconstructable(points, "points.ply"), InputError);
  try {
    reconstruct_surface(points, small_options(), null_reporter());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("extent is 0"));
  }
}

TEST(SampleFrame, ExtentBelowFloatResolutionIsBadInput) {
  // A sphere of radius 1e-4 at 1e3 from the origin: about one float step across.
  const PointCloud points = scaled(synth::sample_sphere(2000, 1.0, 0.0, 1), 1e-4, {1e3, 0.0, 0.0});
  EXPECT_THROW(check_reconstructable(points, "points.ply"), InputError);
  EXPECT_THROW(reconstruct_surface(points, small_options(), null_reporter()), InputError);
}

TEST(SampleFrame, ResultScalesWithTheInput) {
  // Bound: the unit sphere at resolution 32 is within 2% of the radius on
  // average; the same must hold at every scale and position.
  const PointCloud unit = synth::sample_sphere(20000, 1.0, 0.0, 2);
  for (const double scale : {1e-30, 1e-6, 1.0, 1e20}) {
    const Eigen::Vector3d center = Eigen::Vector3d(3.0, -2.0, 1.0) * scale;
    const ReconResult r = reconstruct_surface(scaled(unit, scale, center), small_options(), null_reporter());
    const auto [mean, worst] = relative_radial_error(r.mesh, center, scale);
    SCOPED_TRACE(scale);
    EXPECT_LT(mean, 0.02);
    EXPECT_LT(worst, 0.08);
    EXPECT_GT(r.mesh.num_faces(), 1000u);
    EXPECT_NEAR(r.stats.voxel_size / scale, 1.2 / 32 * 2 * 1.0,
                0.02);  // (1 + 2 margin) * diameter / 32
  }
}

TEST(SampleFrame, FarOutliersAreDroppedAndCounted) {
  for (const double far : {1e6, 1e30}) {
    PointCloud points = synth::sample_sphere(20000, 1.0, 0.0, 3);
    points.positions.emplace_back(static_cast<float>(far), 0.0f, 0.0f);
    points.normals.emplace_back(1.0f, 0.0f, 0.0f);
    hos::testing::MessageLog log;
    const ReconResult r = reconstruct_surface(points, small_options(), log);
    const auto [mean, worst] = relative_radial_error(r.mesh, Eigen::Vector3d::Zero(), 1.0);
    SCOPED_TRACE(far);
    EXPECT_LT(mean, 0.02);
    EXPECT_LT(worst, 0.08);
    EXPECT_THAT(log.warnings(), HasSubstr("1 far outlier points"));
  }
}

TEST(SampleFrame, AbsurdNormalLengthsAreOnlyDirections) {
  PointCloud points = synth::sample_sphere(20000, 1.0, 0.0, 4);
  for (auto& n : points.normals) n *= 1e38f;
  const ReconResult r = reconstruct_surface(points, small_options(), null_reporter());
  EXPECT_LT(relative_radial_error(r.mesh, Eigen::Vector3d::Zero(), 1.0).first, 0.02);
}

TEST(SampleFrame, ConfidenceThatWeighsNothingAnywhereIsBadInputNamingIt) {
  PointCloud points = synth::sample_sphere(2000, 1.0, 0.0, 5);
  points.confidence.assign(points.size(), 0.0f);
  points.confidence[7] = -1.0f;
  points.confidence[8] = std::numeric_limits<float>::quiet_NaN();
  try {
    reconstruct_surface(points, small_options(), null_reporter());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("'confidence'"));
  }
  ReconOptions ignore = small_options();
  ignore.use_confidence = false;
  EXPECT_GT(reconstruct_surface(points, ignore, null_reporter()).mesh.num_faces(), 100u);
}

TEST(SampleFrame, VoxelSizeFarBelowTheDataIsRefusedByTheMemoryCheck) {
  // A sphere of radius 1000: 1.2e10 voxels along each axis, beyond int.
  const PointCloud points = scaled(synth::sample_sphere(2000, 1.0, 0.0, 6), 1000.0, Eigen::Vector3d::Zero());
  ReconOptions o = small_options();
  o.voxel_size = 2e-7;
  try {
    reconstruct_surface(points, o, null_reporter());
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("recon.voxel_size"));
    EXPECT_THAT(e.what(), HasSubstr("more than the budget"));
  }
}

}  // namespace
}  // namespace hos::recon
