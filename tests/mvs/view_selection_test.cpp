// mvs/view_selection.*.
#include "mvs/view_selection.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <set>
#include <tuple>
#include <vector>

#include "tests/mvs/synthetic_workspace.h"

namespace hos::mvs {
namespace {

TEST(ViewSelection, SourcesAreNearbyViewsWithBaseline) {
  const SparseModel& model = mvs_testing::synthetic_workspace().workspace.model;
  MvsOptions options;
  const auto sources = select_source_views(model, options);
  std::size_t i = 0;
  for (const auto& [id, image] : model.images) {
    ASSERT_FALSE(sources[i].empty()) << image.name;
    EXPECT_LE(static_cast<int>(sources[i].size()), options.num_source_views);
    for (int src : sources[i]) {
      EXPECT_NE(src, id);
      const double cos_angle = image.viewing_direction().dot(model.images.at(src).viewing_direction());
      EXPECT_GT(cos_angle, std::cos(100.0 * M_PI / 180.0)) << image.name << " -> " << src;
    }
    ++i;
  }
}

TEST(ViewSelection, ViewWithoutBaselineGetsNoSources) {
  SparseModel model;
  model.cameras[1] = Camera::pinhole(1, 100, 100, 100, 100, 50, 50);
  for (int id : {1, 2}) {
    ImageRecord image;
    image.id = id;
    image.camera_id = 1;
    image.name = std::to_string(id);
    model.images[id] = image;  // identical poses: zero baseline
  }
  for (int k = 0; k < 20; ++k) {
    Point3D p;
    p.id = k;
    p.xyz = Eigen::Vector3d(0.01 * k, 0, 5);
    p.track = {{1, 0}, {2, 0}};
    model.points[k] = p;
  }
  const auto sources = select_source_views(model, MvsOptions{});
  EXPECT_TRUE(sources[0].empty());
  EXPECT_TRUE(sources[1].empty());
}

// Points at the origin seen by a reference view 5 units away, a neighbour
// 10 degrees round and a view 60 degrees round that shares more points: the
// neighbour is the better source (it sees the surface at nearly the same
// angle), unless the falloff is off, when the shared points alone decide.
TEST(ViewSelection, NeighbourBeatsAWideBaselineThatSharesMorePoints) {
  SparseModel model;
  model.cameras[1] = Camera::pinhole(1, 100, 100, 100, 100, 50, 50);
  for (const auto& [id, degrees] : {std::pair{1, 0.0}, {2, 10.0}, {3, 60.0}}) {
    const double a = degrees * M_PI / 180.0;
    ImageRecord image;
    image.id = id;
    image.camera_id = 1;
    image.name = std::to_string(id);
    // Looking at the origin from 5 units away, on a circle about the y axis.
    image.cam_from_world_rotation = Eigen::Quaterniond(Eigen::AngleAxisd(-a, Eigen::Vector3d::UnitY()));
    image.cam_from_world_translation = Eigen::Vector3d(0, 0, 5);
    model.images[id] = image;
  }
  ASSERT_NEAR(model.images.at(3).center().norm(), 5.0, 1e-9);
  for (int k = 0; k < 50; ++k) {
    Point3D p;
    p.id = k;
    p.xyz = Eigen::Vector3d(0.001 * k, 0, 0);
    p.track = {{1, 0}, {k < 20 ? 2 : 3, 0}};  // 20 shared with the neighbour, 30 with the wide view
    model.points[k] = p;
  }
  MvsOptions options;
  options.num_source_views = 1;
  EXPECT_EQ(select_source_views(model, options)[0], std::vector<int>{2});
  options.source_view_angle_falloff_deg = 0.0;
  EXPECT_EQ(select_source_views(model, options)[0], std::vector<int>{3});
}

// Three views see the same 100 points of the reference's left half; a
// fourth, at as good an angle, sees only the 40 of its right half. Ranked by
// shared points (covered weight 1, the default) it is left out; at 0.05,
// points that best_k (2) chosen sources already see count little, and it
// comes in third (5 against its 40).
TEST(ViewSelection, AViewOfWhatTheChosenOnesMissComesInWhenCoveredPointsCountLess) {
  SparseModel model;
  model.cameras[1] = Camera::pinhole(1, 100, 100, 100, 100, 50, 50);
  const Eigen::Vector3d y = Eigen::Vector3d::UnitY(), x = Eigen::Vector3d::UnitX();
  for (const auto& [id, axis, degrees] :
       {std::tuple{1, y, 0.0}, {2, y, 15.0}, {3, y, -15.0}, {4, x, 15.0}, {5, x, -15.0}}) {
    ImageRecord image;
    image.id = id;
    image.camera_id = 1;
    image.name = std::to_string(id);
    // Looking at the origin from 5 units away, turned about the axis.
    image.cam_from_world_rotation = Eigen::Quaterniond(Eigen::AngleAxisd(-degrees * M_PI / 180.0, axis));
    image.cam_from_world_translation = Eigen::Vector3d(0, 0, 5);
    model.images[id] = image;
  }
  for (int k = 0; k < 140; ++k) {
    Point3D p;
    p.id = k;
    const bool left = k < 100;
    p.xyz = Eigen::Vector3d(left ? -0.001 * (k + 1) : 0.001 * (k - 99), 0, 0);
    p.track =
        left ? std::vector<TrackElement>{{1, 0}, {2, 0}, {3, 0}, {4, 0}} : std::vector<TrackElement>{{1, 0}, {5, 0}};
    model.points[k] = p;
  }
  MvsOptions options;
  options.num_source_views = 3;
  std::vector<int> ranked = select_source_views(model, options)[0];
  options.source_view_covered_weight = 0.05;
  const std::vector<int> covering = select_source_views(model, options)[0];
  std::sort(ranked.begin(), ranked.end());
  EXPECT_EQ(ranked, (std::vector<int>{2, 3, 4}));
  ASSERT_EQ(covering.size(), 3u);
  EXPECT_EQ(covering.back(), 5);
}

TEST(ViewSelection, FusionChecksEveryOtherViewUpToItsLimit) {
  const SparseModel& model = mvs_testing::synthetic_workspace().workspace.model;
  ASSERT_EQ(model.images.size(), 12u);
  for (int limit : {0, 11, 30}) {
    for (const auto& views : select_fusion_views(model, limit)) EXPECT_EQ(views.size(), 11u) << limit;
  }
}

// Views mvs skips have no depth map: no view checks against them, and the
// others take their place within the limit.
TEST(ViewSelection, FusionLeavesOutViewsWithoutDepthMaps) {
  const SparseModel& model = mvs_testing::synthetic_workspace().workspace.model;
  const std::vector<std::vector<int>> all = select_fusion_views(model, 3);
  const std::set<int> without_depth{all[0][0], all[0][1]};
  for (int limit : {0, 3}) {
    const auto chosen = select_fusion_views(model, limit, without_depth);
    std::size_t i = 0;
    for (const auto& [id, image] : model.images) {
      const std::size_t others = 11 - without_depth.size() + without_depth.count(id);
      EXPECT_EQ(chosen[i].size(), limit == 0 ? others : 3u) << image.name;
      for (int other : chosen[i]) EXPECT_FALSE(without_depth.contains(other)) << image.name;
      ++i;
    }
  }
  // The first view's list moves up: its third choice and the two after it.
  const auto all5 = select_fusion_views(model, 5);
  EXPECT_EQ(select_fusion_views(model, 3, without_depth)[0], std::vector<int>(all5[0].begin() + 2, all5[0].end()));
}

// Over the limit, the views sharing the most sparse points, most first.
TEST(ViewSelection, FusionViewsOverTheLimitShareTheMostPoints) {
  const SparseModel& model = mvs_testing::synthetic_workspace().workspace.model;
  const auto shared = [&](int a, int b) {
    int n = 0;
    for (const auto& [id, point] : model.points) {
      bool sa = false, sb = false;
      for (const auto& e : point.track) {
        sa = sa || e.image_id == a;
        sb = sb || e.image_id == b;
      }
      n += sa && sb;
    }
    return n;
  };
  const auto chosen = select_fusion_views(model, 3);
  std::size_t i = 0;
  for (const auto& [id, image] : model.images) {
    ASSERT_EQ(chosen[i].size(), 3u) << image.name;
    EXPECT_GE(shared(id, chosen[i][0]), shared(id, chosen[i][1]));
    EXPECT_GE(shared(id, chosen[i][1]), shared(id, chosen[i][2]));
    for (const auto& [other, unused] : model.images) {
      const bool in = std::find(chosen[i].begin(), chosen[i].end(), other) != chosen[i].end();
      if (other != id && !in) {
        EXPECT_LE(shared(id, other), shared(id, chosen[i][2])) << image.name;
      }
    }
    ++i;
  }
}

}  // namespace
}  // namespace hos::mvs
