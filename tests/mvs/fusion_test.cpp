// mvs/fusion.* alone, on synthetic depth maps whose agreement is known
// exactly: four cameras side by side look at the plane z = 5; neighbouring
// cameras are 0.1 apart, so a surface point moves by exactly 2 pixels from
// one view to the next and every point of the plane is seen by a known set
// of views.
#include "mvs/fusion.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "mvs/fusion_store.h"
#include "tests/support/test_support.h"

namespace hos::mvs {
namespace {

constexpr int kMapWidth = 64, kMapHeight = 48, kViews = 4, kShift = 2;  // pixels between neighbouring views
constexpr double kDepth = 5.0;

FusionView fusion_plane_view(int j) {
  FusionView v;
  v.K << 100, 0, kMapWidth / 2.0, 0, 100, kMapHeight / 2.0, 0, 0, 1;
  v.K_inv = v.K.inverse();
  v.t = -Eigen::Vector3d(0.1 * j, 0, 0);  // R = I, centre (0.1 j, 0, 0)
  v.map = FusionMap(DepthMap{cv::Mat(kMapHeight, kMapWidth, CV_32F, cv::Scalar(kDepth)),
                             cv::Mat(kMapHeight, kMapWidth, CV_32FC3, cv::Scalar(0, 0, -1)),
                             cv::Mat(kMapHeight, kMapWidth, CV_32F, cv::Scalar(0.1))});
  v.color = cv::Mat(kMapHeight, kMapWidth, CV_8UC3, cv::Scalar(0, 0, 40 * j));  // BGR: red = 40 j
  return v;
}

std::vector<FusionView> fusion_plane_views() {
  std::vector<FusionView> views;
  views.reserve(kViews);
  for (int j = 0; j < kViews; ++j) views.push_back(fusion_plane_view(j));
  return views;
}

// Column u of view 0 (possibly outside it) is column u - kShift j of view j.
// Expected points: one per row and per column seen by enough agreeing views,
// with that many views as confidence.
std::map<int, int> expected_confidence(const std::vector<bool>& agreeing, int min_views) {
  std::map<int, int> confidence;
  for (int u = -kShift * kViews; u < kMapWidth + kShift * kViews; ++u) {
    int seen = 0;
    for (int j = 0; j < kViews; ++j) seen += agreeing[j] && u - kShift * j >= 0 && u - kShift * j < kMapWidth;
    if (seen >= min_views) confidence[u] = seen;
  }
  return confidence;
}

void expect_fused(const PointCloud& cloud, const std::map<int, int>& expected) {
  ASSERT_EQ(cloud.size(), expected.size() * kMapHeight);
  std::map<int, int> columns;  // column of view 0 -> points
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d p = cloud.positions[i].cast<double>();
    EXPECT_NEAR(p.z(), kDepth, 1e-5);
    EXPECT_NEAR(cloud.normals[i].cast<double>().dot(Eigen::Vector3d(0, 0, -1)), 1.0, 1e-6);
    // Back into view 0's columns: x = f X / Z + cx - 0.5 at the pixel centre.
    const int u = static_cast<int>(std::lround(100.0 * p.x() / p.z() + kMapWidth / 2.0 - 0.5));
    ++columns[u];
    ASSERT_TRUE(expected.count(u)) << "column " << u;
    EXPECT_EQ(cloud.confidence[i], expected.at(u)) << "column " << u;
  }
  for (const auto& [u, count] : columns) EXPECT_EQ(count, kMapHeight) << "column " << u;  // each point once
}

// The tests state their thresholds: a point needs the reference and
// min_views - 1 more views; neighbouring cameras are atan(0.1 / 5) = 1.15
// degrees apart at the plane, so they count as distinct below that angle;
// two-view points off unless a test turns them on; every pixel fused (no
// density control) so each agreeing pixel is one point.
MvsOptions views_must_agree(int min_views) {
  MvsOptions options;
  options.fusion_spacing_px = 0;
  options.min_consistent_views = min_views - 1;
  options.min_triangulation_angle_deg = 1.0;
  options.two_view_max_cost = 0.0;
  return options;
}

MvsOptions three_views_must_agree() { return views_must_agree(3); }

TEST(Fusion, AgreeingPlaneIsFusedOncePerPointWithItsViewCount) {
  const MvsOptions options = three_views_must_agree();
  const PointCloud cloud = fuse_depth_maps(fusion_plane_views(), options, null_reporter());
  expect_fused(cloud, expected_confidence({true, true, true, true}, 3));
  // Colours are the mean over the agreeing views: red 40 j averaged.
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.confidence[i] == 4) {
      EXPECT_EQ(cloud.colors[i][0], 60);
    }
  }
}

TEST(Fusion, StricterConsistencyKeepsOnlyPointsSeenByMoreViews) {
  expect_fused(fuse_depth_maps(fusion_plane_views(), views_must_agree(4), null_reporter()),
               expected_confidence({true, true, true, true}, 4));
}

TEST(Fusion, ViewWithWrongDepthDoesNotCount) {
  auto views = fusion_plane_views();
  views[3].map.depth.setTo(kDepth * 1.05);  // 5% off; max_depth_error is 1%
  expect_fused(fuse_depth_maps(views, three_views_must_agree(), null_reporter()),
               expected_confidence({true, true, true, false}, 3));
}

TEST(Fusion, ViewWithWrongNormalsDoesNotCount) {
  auto views = fusion_plane_views();
  const double a = 30.0 * M_PI / 180.0;  // max_normal_error_deg is 20
  views[1].map.normal.setTo(encode_normal({std::sin(a), 0, -std::cos(a)}));
  expect_fused(fuse_depth_maps(views, three_views_must_agree(), null_reporter()),
               expected_confidence({true, false, true, true}, 3));
}

// Views 0 and 1 see the plane; views 2 and 3 see nearer things that agree
// with nothing (depths 4 and 3), which hide the plane from them.
std::vector<FusionView> plane_seen_by_two_views() {
  auto views = fusion_plane_views();
  views[2].map.depth.setTo(4.0);
  views[3].map.depth.setTo(3.0);
  return views;
}

TEST(Fusion, TwoViewPointsNeedALowCostOnBothPixels) {
  auto views = plane_seen_by_two_views();
  MvsOptions options = three_views_must_agree();
  EXPECT_EQ(fuse_depth_maps(views, options, null_reporter()).size(), 0u);  // two_view_max_cost 0: never
  options.two_view_max_cost = 0.2;                                         // the maps' cost is 0.1
  expect_fused(fuse_depth_maps(views, options, null_reporter()), expected_confidence({true, true, false, false}, 2));
  views[1].map.cost.setTo(0.3);  // one pixel of the pair matched worse than allowed
  EXPECT_EQ(fuse_depth_maps(views, options, null_reporter()).size(), 0u);
}

TEST(Fusion, TwoViewPointsAreDroppedWhereAnotherViewSeesNothing) {
  auto views = plane_seen_by_two_views();
  MvsOptions options = three_views_must_agree();
  options.two_view_max_cost = 0.2;
  // View 2 has no depth on its right half (image columns 32..63, which see
  // the plane's columns 36..67 of view 0); view 3 still sees a nearer thing.
  views[2].map.depth.colRange(kMapWidth / 2, kMapWidth).setTo(0);
  std::map<int, int> expected = expected_confidence({true, true, false, false}, 2);
  for (int u = kMapWidth / 2 + 2 * kShift; u < kMapWidth + 2 * kShift; ++u) expected.erase(u);
  expect_fused(fuse_depth_maps(views, options, null_reporter()), expected);
  // Allowing one such view keeps them all again.
  options.two_view_max_views_without_depth = 1;
  expect_fused(fuse_depth_maps(views, options, null_reporter()), expected_confidence({true, true, false, false}, 2));
}

TEST(Fusion, AViewSeeingTheSurfaceGrazinglyDoesNotSpeakAgainstIt) {
  // As above, view 2 has no depth on its right half, which sees the plane's
  // points at x in [0.2, 1.8]. Their normals are tilted by t about the y axis
  // (towards -x): view 2 sees them at incidence between about t - 18 and t
  // degrees (30 degrees: at most 30; 80 degrees: at least 62).
  auto views = plane_seen_by_two_views();
  views[2].map.depth.colRange(kMapWidth / 2, kMapWidth).setTo(0);
  MvsOptions options = three_views_must_agree();
  options.two_view_max_cost = 0.2;
  options.two_view_veto_max_incidence_deg = 60.0;
  std::map<int, int> vetoed = expected_confidence({true, true, false, false}, 2);
  for (int u = kMapWidth / 2 + 2 * kShift; u < kMapWidth + 2 * kShift; ++u) vetoed.erase(u);
  const auto tilt_normals = [&views](double degrees) {
    const double t = degrees * M_PI / 180.0;
    for (auto& v : views) v.map.normal.setTo(encode_normal({-std::sin(t), 0, -std::cos(t)}));
  };
  tilt_normals(30.0);  // view 2 faces the surface: its missing depth still counts
  const PointCloud facing = fuse_depth_maps(views, options, null_reporter());
  EXPECT_EQ(facing.size(), vetoed.size() * kMapHeight);
  tilt_normals(80.0);  // view 2 sees it grazingly: the points stay
  const PointCloud grazing = fuse_depth_maps(views, options, null_reporter());
  EXPECT_EQ(grazing.size(), expected_confidence({true, true, false, false}, 2).size() * kMapHeight);
}

TEST(Fusion, PhotoFromTheSameSpotIsNoFurtherEvidence) {
  // Views 0, 1 and a second photo from view 0's spot agree on the plane.
  auto views = plane_seen_by_two_views();
  views[2] = fusion_plane_view(0);
  views[3].map.depth.setTo(0);
  const PointCloud cloud = fuse_depth_maps(views, three_views_must_agree(), null_reporter());
  EXPECT_EQ(cloud.size(), 0u);  // two distinct viewpoints only
  MvsOptions any_angle = three_views_must_agree();
  any_angle.min_triangulation_angle_deg = 0.0;  // every photo counts: three views agree
  EXPECT_GT(fuse_depth_maps(views, any_angle, null_reporter()).size(), 0u);
}

TEST(Fusion, CompactNormalsKeepTheirDirectionWithinAHundredthOfADegree) {
  std::vector<Eigen::Vector3d> normals = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, {1, -1, -1e-9}};
  std::uint64_t state = 1;
  const auto uniform = [&state] {  // deterministic, in [-1, 1)
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) / 4503599627370496.0 - 1.0;
  };
  for (int i = 0; i < 10000; ++i) normals.emplace_back(uniform(), uniform(), uniform());
  double worst_deg = 0;
  for (const Eigen::Vector3d& n : normals) {
    const Eigen::Vector3d u = n.normalized(), back = decode_normal(encode_normal(n));
    worst_deg = std::max(worst_deg, std::acos(std::min(1.0, u.dot(back))) * 180.0 / M_PI);
  }
  EXPECT_LT(worst_deg, 0.01);
  // Pixels without depth have a zero normal: it must decode to a number.
  const Eigen::Vector3d zero = decode_normal(encode_normal(Eigen::Vector3d::Zero()));
  EXPECT_TRUE(zero.allFinite());
  EXPECT_NEAR(zero.norm(), 1.0, 1e-12);
}

// Each view's neighbours: the views at most `reach` indices away.
std::vector<std::vector<std::size_t>> neighbours_within(int reach) {
  std::vector<std::vector<std::size_t>> neighbours(kViews);
  for (int r = 0; r < kViews; ++r) {
    for (int s = 0; s < kViews; ++s) {
      if (s != r && std::abs(s - r) <= reach) neighbours[r].push_back(static_cast<std::size_t>(s));
    }
  }
  return neighbours;
}

// Fusion through a store: views added in order, a budget in views.
PointCloud fuse_in_store(const hos::testing::TempDir& spill,
                         std::size_t budget_views,
                         const std::vector<std::vector<std::size_t>>& neighbours,
                         const MvsOptions& options,
                         int* spilled = nullptr) {
  const auto bytes = static_cast<std::size_t>(kMapWidth * kMapHeight * fusion_bytes_per_pixel());
  FusionViewStore store(budget_views * bytes, spill.path());
  for (int j = 0; j < kViews; ++j) store.add(fusion_plane_view(j));
  PointCloud cloud = fuse_depth_maps(store, neighbours, options, null_reporter());
  if (spilled) *spilled = store.spilled_views();
  return cloud;
}

void expect_same_points(const PointCloud& streamed, const PointCloud& in_memory) {
  ASSERT_GT(in_memory.size(), 0u);
  ASSERT_EQ(streamed.size(), in_memory.size());
  for (std::size_t i = 0; i < in_memory.size(); ++i) {
    ASSERT_EQ(streamed.positions[i], in_memory.positions[i]) << i;
    ASSERT_EQ(streamed.normals[i], in_memory.normals[i]) << i;
    ASSERT_EQ(streamed.colors[i], in_memory.colors[i]) << i;
    ASSERT_EQ(streamed.confidence[i], in_memory.confidence[i]) << i;
  }
}

TEST(Fusion, MapsSpilledOverTheMemoryBudgetFuseToTheSamePoints) {
  const hos::testing::TempDir spill;
  const MvsOptions options = views_must_agree(2);
  int spilled = 0;
  // Every view checked against every other: all are held, none is dropped.
  expect_same_points(fuse_in_store(spill, 1, neighbours_within(kViews), options, &spilled),
                     fuse_depth_maps(fusion_plane_views(), options, null_reporter()));
  EXPECT_EQ(spilled, kViews - 1);
  // Against the next views only: views are dropped and read back in turn.
  expect_same_points(fuse_in_store(spill, 1, neighbours_within(1), options, &spilled),
                     fuse_in_store(spill, 0, neighbours_within(1), options));
  EXPECT_EQ(spilled, kViews);
}

TEST(Fusion, OnlyTheListedNeighboursConfirmAPoint) {
  const hos::testing::TempDir spill;
  const MvsOptions options = views_must_agree(2);
  const auto max_confidence = [](const PointCloud& cloud) {
    float m = 0;
    for (float c : cloud.confidence) m = std::max(m, c);
    return m;
  };
  const PointCloud all = fuse_in_store(spill, 0, neighbours_within(kViews), options);
  EXPECT_EQ(max_confidence(all), 4.0f);
  // A view and the ones next to it: fewer agree on a point.
  const PointCloud adjacent = fuse_in_store(spill, 0, neighbours_within(1), options);
  ASSERT_GT(adjacent.size(), 0u);
  EXPECT_LT(max_confidence(adjacent), 4.0f);
  EXPECT_EQ(fuse_in_store(spill, 0, neighbours_within(0), options).size(), 0u);
}

TEST(Fusion, PixelsWithoutDepthAreIgnored) {
  auto views = fusion_plane_views();
  for (auto& v : views) v.map.depth.setTo(0);
  EXPECT_EQ(fuse_depth_maps(views, three_views_must_agree(), null_reporter()).size(), 0u);
}

}  // namespace
}  // namespace hos::mvs
