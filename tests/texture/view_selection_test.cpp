#include "texture/view_selection.h"

#include <gtest/gtest.h>

#include "tests/texture/scene_fixtures.h"

namespace hos::texture {
namespace {

using testing::strip_topology;

FaceViewSample sample(int view, float quality) {
  FaceViewSample s;
  s.view = view;
  s.gradient_integral = quality;
  s.visible_px = 1.0f;
  s.projected_area_px = 1.0f;
  s.cos_angle = 1.0f;
  return s;
}

// Two views see all faces; view 1 is slightly better on odd faces only.
FaceViewCandidates alternating(int n) {
  FaceViewCandidates c;
  c.offsets.push_back(0);
  for (int i = 0; i < n; ++i) {
    c.samples.push_back(sample(0, 10.0f));
    c.samples.push_back(sample(1, i % 2 == 1 ? 11.0f : 9.0f));
    c.offsets.push_back(static_cast<int>(c.samples.size()));
  }
  return c;
}

TEST(ViewSelection, WithoutSmoothnessEachFaceTakesItsBestView) {
  TextureOptions options;
  options.smoothness = 0.0;
  options.gradient_floor = 0.0;
  const auto selection = select_views(strip_topology(10), alternating(10), options, null_reporter());
  for (int i = 0; i < 10; ++i) EXPECT_EQ(selection.labels[i], i % 2);
}

TEST(ViewSelection, PottsSmoothnessMergesPatches) {
  TextureOptions options;
  options.smoothness = 0.5;
  options.gradient_floor = 0.0;
  const auto selection = select_views(strip_topology(10), alternating(10), options, null_reporter());
  for (int i = 1; i < 10; ++i) EXPECT_EQ(selection.labels[i], selection.labels[0]);
  EXPECT_DOUBLE_EQ(selection.smoothness_energy, 0.0);
}

TEST(ViewSelection, InvisibleViewIsNeverChosenAndUnseenFacesStayUnlabelled) {
  FaceViewCandidates c;
  c.offsets = {0, 1, 1, 2};
  c.samples = {sample(0, 1.0f), sample(1, 1.0f)};  // face 1 unseen
  TextureOptions options;
  options.smoothness = 10.0;
  const auto selection = select_views(strip_topology(3), c, options, null_reporter());
  EXPECT_EQ(selection.labels[0], 0);
  EXPECT_EQ(selection.labels[1], -1);
  EXPECT_EQ(selection.labels[2], 1);
  EXPECT_EQ(selection.num_unseen, 1);
}

TEST(ViewSelection, OutlierViewIsRejected) {
  FaceViewCandidates c;
  c.offsets = {0, 4};
  for (int v = 0; v < 4; ++v) {
    FaceViewSample s = sample(v, 1.0f);
    s.mean_rgb = v == 2 ? Eigen::Vector3f(250, 10, 10) : Eigen::Vector3f(100 + v, 120, 90);
    c.samples.push_back(s);
  }
  TextureOptions options;
  EXPECT_EQ(reject_outlier_views(c, options), 1);
  ASSERT_EQ(c.samples.size(), 3u);
  for (const auto& s : c.samples) EXPECT_NE(s.view, 2);
}

}  // namespace
}  // namespace hos::texture
