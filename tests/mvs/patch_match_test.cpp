// mvs/patch_match.*: PatchMatch on two views of a textured fronto-parallel
// plane, made in memory so the true depth of every pixel is known.
#include "mvs/patch_match.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <opencv2/imgproc.hpp>

namespace hos::mvs {
namespace {

constexpr int kWidth = 160, kHeight = 120;
constexpr double kFocal = 200.0;
constexpr double kPlaneDepth = 4.0;
constexpr int kDisparity = 8;  // pixels; the source camera sits kDisparity * kPlaneDepth / kFocal along +x

// A smooth random texture, wider than a view by extra columns.
cv::Mat texture(int extra = kDisparity) {
  cv::Mat noise(kHeight, kWidth + extra, CV_32F);
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

// The left half of the reference view is seen by one of its two sources
// only (the other's frame ends at the middle). With the best two of two
// sources averaged, the source that does not see a window counts as
// mvs.unseen_view_cost: at 2 (the worst match) that half cannot reach
// max_cost; at 1 its depth is found, while the right half, which both
// sources see, is found either way.
TEST(PatchMatch, ASurfaceOnlyOneSourceSeesMatchesWhenAnUnseenViewCostsLess) {
  const int half = kWidth / 2;
  const cv::Mat tex = texture(half);
  const MvsView ref = plane_view(tex, 0, 0.0);
  const MvsView near = plane_view(tex, kDisparity, kDisparity * kPlaneDepth / kFocal);
  const MvsView far = plane_view(tex, half, half * kPlaneDepth / kFocal);  // sees the ref's columns >= half
  const auto correct_shares = [&](double unseen_view_cost) {
    MvsOptions options;
    options.best_k = 2;
    options.unseen_view_cost = unseen_view_cost;
    const DepthMap map = to_depth_map(
        match_planes(ref, {&near, &far}, kPlaneDepth / 2, kPlaneDepth * 2, {}, options, null_reporter()), ref, options);
    int left = 0, right = 0, total = 0;
    for (int y = 10; y < kHeight - 10; ++y) {
      for (int x = 10; x < half - 10; ++x) {
        ++total;
        left += std::abs(map.depth.at<float>(y, x) - kPlaneDepth) <= 0.005 * kPlaneDepth;
        right += std::abs(map.depth.at<float>(y, x + half) - kPlaneDepth) <= 0.005 * kPlaneDepth;
      }
    }
    return std::pair{double(left) / total, double(right) / total};
  };
  const auto [left_worst, right_worst] = correct_shares(2.0);
  const auto [left, right] = correct_shares(1.0);
  std::cout << "one-source half matched: " << left_worst << " at 2, " << left
            << " at 1; both-source half: " << right_worst << ", " << right << "\n";
  EXPECT_LE(left_worst, 0.05);
  EXPECT_GE(left, 0.8);
  EXPECT_GE(right_worst, 0.8);
  EXPECT_GE(right, 0.8);
}

// A plane no source sees is not scored, whatever an unseen view costs: with
// one source, which sees only the reference's right half, and
// unseen_view_cost 0, a plane that pushes the window out of the source's
// frame must not be a free match. Chance matches inside the frame may give
// the left half wrong depths, but none whose window the source cannot see.
TEST(PatchMatch, APlaneNoSourceSeesIsNotScoredEvenWhenUnseenViewsCostNothing) {
  const int half = kWidth / 2;
  const double baseline = half * kPlaneDepth / kFocal;
  const cv::Mat tex = texture(half);
  const MvsView ref = plane_view(tex, 0, 0.0);
  const MvsView far = plane_view(tex, half, baseline);  // sees the ref's columns >= half at the plane's depth
  MvsOptions options;
  options.best_k = 1;
  options.unseen_view_cost = 0.0;
  const DepthMap map = to_depth_map(
      match_planes(ref, {&far}, kPlaneDepth / 2, kPlaneDepth * 2, {}, options, null_reporter()), ref, options);
  int with_depth = 0, unseen = 0;
  for (int y = 10; y < kHeight - 10; ++y) {
    for (int x = 10; x < half; ++x) {
      const float depth = map.depth.at<float>(y, x);
      if (!(depth > 0)) continue;
      ++with_depth;
      // The pixel's column in the source at that depth, well off its frame.
      unseen += x + 0.5 - kFocal * baseline / depth < -10.0;
    }
  }
  std::cout << "left half: " << with_depth << " depths, " << unseen << " of them unseen by the source\n";
  EXPECT_EQ(unseen, 0);
}

}  // namespace
}  // namespace hos::mvs
