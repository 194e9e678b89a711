#include "core/nearest_rotation.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace hos {
namespace {

// A rotation scaled and slightly perturbed: its nearest rotation is the
// rotation itself, to within the perturbation.
TEST(NearestRotation, RecoversAScaledNoisyRotation3d) {
  const Eigen::Matrix3d rotation =
      (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, -0.5).normalized())).toRotationMatrix();
  Eigen::Matrix3d noise;
  noise << 1e-4, -2e-4, 0.0, 3e-4, 0.0, 1e-4, -1e-4, 2e-4, -3e-4;
  const Eigen::Matrix3d r = nearest_rotation(Eigen::Matrix3d(2.5 * rotation + noise));
  EXPECT_LT((r - rotation).norm(), 1e-3);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
}

// A reflection's nearest proper rotation flips the axis of the smallest
// singular value: diag(3, 2, -1) -> the identity.
TEST(NearestRotation, ReplacesAReflectionByARotation3d) {
  const Eigen::Matrix3d r = nearest_rotation(Eigen::Matrix3d(Eigen::Vector3d(3.0, 2.0, -1.0).asDiagonal()));
  EXPECT_LT((r - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(NearestRotation, ClosedFormIn2dMatchesTheAngle) {
  const Eigen::Matrix2d rotation = Eigen::Rotation2Dd(-2.0).toRotationMatrix();
  EXPECT_LT((nearest_rotation(Eigen::Matrix2d(0.3 * rotation)) - rotation).norm(), 1e-12);
  // A reflection diag(1, -1) in 2D: its trace is maximised by the identity among rotations.
  Eigen::Matrix2d reflection;
  reflection << 2.0, 0.0, 0.0, -1.0;
  EXPECT_LT((nearest_rotation(reflection) - Eigen::Matrix2d::Identity()).norm(), 1e-12);
}

}  // namespace
}  // namespace hos
