// mvs/planar_prior.*: a textureless hole in a plane gets the plane's depth
// from its confident surroundings; no prior bridges a depth step.
#include "mvs/planar_prior.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

namespace hos::mvs {
namespace {

constexpr int kPriorWidth = 160, kPriorHeight = 120;

Eigen::Matrix3d intrinsics() {
  Eigen::Matrix3d K;
  K << 150, 0, 80, 0, 150, 60, 0, 0, 1;
  return K;
}

// The depth of the plane n . x = offset along pixel (x, y)'s ray.
double plane_depth(const Eigen::Vector3d& n, double offset, double x, double y) {
  return offset / n.dot(intrinsics().inverse() * Eigen::Vector3d(x, y, 1.0));
}

// A plane map of the plane n . x = offset (camera frame, n towards the
// camera), confident (cost 0.05) except in the rectangle hole, where it holds
// what a textureless window leaves: a wrong depth at the worst cost.
PlaneMap plane_with_hole(const Eigen::Vector3d& n, double offset, const cv::Rect& hole) {
  PlaneMap map;
  map.K = intrinsics();
  map.depth = cv::Mat(kPriorHeight, kPriorWidth, CV_32F);
  map.normal = cv::Mat(kPriorHeight, kPriorWidth, CV_32FC3, cv::Vec3f(float(n.x()), float(n.y()), float(n.z())));
  map.cost = cv::Mat(kPriorHeight, kPriorWidth, CV_32F, cv::Scalar(0.05));
  for (int y = 0; y < kPriorHeight; ++y) {
    for (int x = 0; x < kPriorWidth; ++x) map.depth.at<float>(y, x) = float(plane_depth(n, offset, x + 0.5, y + 0.5));
  }
  map.depth(hole).setTo(0.3);
  map.cost(hole).setTo(3.0);
  map.normal(hole).setTo(cv::Vec3f(0, 0, -1));
  return map;
}

TEST(PlanarPrior, TexturelessHoleInAPlaneGetsThePlanesDepth) {
  // Ground seen obliquely: 70 degrees between the plane's normal and the
  // optical axis.
  const double tilt = 70.0 * M_PI / 180.0;
  const Eigen::Vector3d n(0.0, -std::sin(tilt), -std::cos(tilt));
  const double offset = n.dot(Eigen::Vector3d(0, 0, 5));
  const cv::Rect hole(50, 40, 50, 40);
  const PriorPlanes prior = planar_prior(plane_with_hole(n, offset, hole), 0.2);
  int filled = 0;
  for (int y = hole.y; y < hole.y + hole.height; ++y) {
    for (int x = hole.x; x < hole.x + hole.width; ++x) {
      const float d = prior.depth.at<float>(y, x);
      ASSERT_GT(d, 0.0f) << x << "," << y;
      EXPECT_NEAR(d, plane_depth(n, offset, x + 0.5, y + 0.5), 1e-4 * d) << x << "," << y;
      const cv::Vec3f pn = prior.normal.at<cv::Vec3f>(y, x);
      EXPECT_GT(Eigen::Vector3d(pn[0], pn[1], pn[2]).dot(n), std::cos(0.5 * M_PI / 180.0));
      ++filled;
    }
  }
  EXPECT_EQ(filled, hole.area());
}

TEST(PlanarPrior, NoPriorBridgesADepthStep) {
  // Two fronto-parallel planes, depth 2 on the left and 4 on the right.
  PlaneMap map = plane_with_hole(Eigen::Vector3d(0, 0, -1), -2.0, cv::Rect(0, 0, 1, 1));
  map.cost.setTo(0.05);
  map.depth.colRange(kPriorWidth / 2, kPriorWidth).setTo(4.0);
  const PriorPlanes prior = planar_prior(map, 0.2);
  int with_prior = 0;
  for (int y = 0; y < kPriorHeight; ++y) {
    for (int x = 0; x < kPriorWidth; ++x) {
      const float d = prior.depth.at<float>(y, x);
      if (d == 0.0f) continue;
      ++with_prior;
      EXPECT_TRUE(std::abs(d - 2.0f) < 1e-3f || std::abs(d - 4.0f) < 1e-3f) << x << "," << y << ": " << d;
    }
  }
  EXPECT_GT(with_prior, kPriorWidth * kPriorHeight / 2);
}

TEST(PlanarPrior, NothingConfidentGivesNoPrior) {
  PlaneMap map = plane_with_hole(Eigen::Vector3d(0, 0, -1), -2.0, cv::Rect(0, 0, kPriorWidth, kPriorHeight));
  const PriorPlanes prior = planar_prior(map, 0.2);
  EXPECT_EQ(cv::countNonZero(prior.depth), 0);
}

}  // namespace
}  // namespace hos::mvs
