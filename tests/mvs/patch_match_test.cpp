// mvs/patch_match.*: PatchMatch on two views of a textured fronto-parallel
// plane, made in memory so the true depth of every pixel is known.
#include "mvs/patch_match.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace hos::mvs {
namespace {

constexpr int kWidth = 160, kHeight = 120;
constexpr double kFocal = 200.0;
constexpr double kPlaneDepth = 4.0;
constexpr int kDisparity = 8;  // pixels; the source camera sits kDisparity * kPlaneDepth / kFocal along +x

// A smooth random texture, larger than a view by the disparity.
cv::Mat texture() {
  cv::Mat noise(kHeight, kWidth + kDisparity, CV_32F);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 1.2);
  cv::normalize(noise, noise, 0.0, 1.0, cv::NORM_MINMAX);
  return noise;
}

// A view of the plane z = kPlaneDepth from a camera at (centre_x, 0, 0)
// looking down +z: it sees texture column u + shift at its column u.
MvsView plane_view(const cv::Mat& tex, int shift, double centre_x) {
  MvsView v;
  v.gray = tex(cv::Rect(shift, 0, kWidth, kHeight)).clone();
  cv::Mat gray8;
  v.gray.convertTo(gray8, CV_8U, 255.0);
  cv::cvtColor(gray8, v.color, cv::COLOR_GRAY2BGR);
  v.K << kFocal, 0, kWidth / 2.0, 0, kFocal, kHeight / 2.0, 0, 0, 1;
  v.K_inv = v.K.inverse();
  v.t = Eigen::Vector3d(-centre_x, 0, 0);
  return v;
}

// The reference view (at the origin) and the source view of the plane.
struct PlaneViews {
  MvsView ref, src;
};
PlaneViews plane_views() {
  const cv::Mat tex = texture();
  return {plane_view(tex, 0, 0.0), plane_view(tex, kDisparity, kDisparity * kPlaneDepth / kFocal)};
}

// Share of the pixels within radius (Chebyshev) of (cx, cy) whose depth is
// the plane's within 0.5%.
double correct_share_near(const PlaneMap& planes, int cx, int cy, int radius) {
  int correct = 0, total = 0;
  for (int y = cy - radius; y <= cy + radius; ++y) {
    for (int x = cx - radius; x <= cx + radius; ++x) {
      ++total;
      correct += std::abs(planes.depth.at<float>(y, x) - kPlaneDepth) <= 0.005 * kPlaneDepth;
    }
  }
  return double(correct) / total;
}

// One sweep from a single sparse point: the seeded plane spreads by
// propagation alone (random planes rarely hit it). Propagation that reaches
// 11 pixels along each axis (adaptive checkerboard sampling) covers most of
// the 17x17 pixels around the seed in one sweep; reaching 3 pixels covered
// 0.41 of them.
TEST(PatchMatch, OneSweepCarriesASeededPlaneElevenPixelsAlongTheAxes) {
  const auto [ref, src] = plane_views();
  MvsOptions options;
  options.iterations = 1;
  options.best_k = 1;
  const int cx = kWidth / 2, cy = kHeight / 2;
  const Eigen::Vector3d seed = ref.K_inv * Eigen::Vector3d(cx + 0.5, cy + 0.5, 1.0) * kPlaneDepth;
  const PlaneMap planes = match_planes(ref, {&src}, kPlaneDepth / 2, kPlaneDepth * 2, {seed}, options, null_reporter());
  EXPECT_LE(std::abs(planes.depth.at<float>(cy, cx) - kPlaneDepth), 1e-3);
  EXPECT_GE(correct_share_near(planes, cx, cy, 8), 0.7);
}

// A finer level whose coarse planes all missed the surface (half a view's
// size, every plane 1.5 times too deep): random planes tried before the
// sweep give propagation something to carry: with 6, one sweep recovered
// 0.74 of the surface around the centre; without, 0.10.
TEST(PatchMatch, RandomPlanesLetAFinerLevelFindWhatTheCoarseOneMissed) {
  const PlaneViews views = plane_views();  // named members: the lambda below captures them
  const MvsView &ref = views.ref, &src = views.src;
  PlaneMap coarse;
  coarse.depth = cv::Mat(kHeight / 2, kWidth / 2, CV_32F, cv::Scalar(1.5 * kPlaneDepth));
  coarse.normal = cv::Mat(kHeight / 2, kWidth / 2, CV_32FC3, cv::Scalar(0, 0, -1));
  coarse.cost = cv::Mat(kHeight / 2, kWidth / 2, CV_32F, cv::Scalar(1.0));
  coarse.K = ref.K;
  coarse.K.topRows(2) *= 0.5;
  const auto recovered = [&](int random_planes) {
    MvsOptions options;
    options.best_k = 1;
    options.refine_iterations = 1;
    options.refine_random_planes = random_planes;
    const PlaneMap fine =
        refine_planes(ref, {&src}, {}, coarse, kPlaneDepth / 2, kPlaneDepth * 2, {}, options, null_reporter());
    return correct_share_near(fine, kWidth / 2, kHeight / 2, 40);
  };
  const double without = recovered(0), with = recovered(6);
  EXPECT_GE(with, 0.6);
  EXPECT_GE(with, without + 0.3);
}

}  // namespace
}  // namespace hos::mvs
