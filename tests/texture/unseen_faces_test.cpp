// texture/unseen_faces.*: faces no photo sees take the colours of the seen
// surface around them, never the photos' black background.
#include "texture/unseen_faces.h"

#include <gtest/gtest.h>

#include <iostream>
#include <opencv2/core.hpp>

#include "synth/shapes.h"
#include "tests/texture/scene_fixtures.h"
#include "texture/texture_mesh.h"

namespace hos::texture {
namespace {

using testing::make_view;
using testing::render_sphere;
using testing::sample_atlas;
using testing::six_views_of_sphere;
using testing::texture_points;
using testing::view_name;

// The true albedo is at least 0.2 (51) in every channel (sphere_albedo); the
// photos' background is black.
constexpr float kDarkestAlbedo = 51.0f;

// Six photos from 40 degrees above the unit sphere: its lower part is seen
// by none, and the faces that border it are seen edge-on, along the
// silhouette. The mesh stands 2% outside the true sphere, as a
// reconstruction's surface may by a voxel, so those faces' pixels reach
// into the background.
TextureResult texture_sphere_seen_from_above(UnseenFaces mode) {
  TextureOptions options;
  options.unseen = mode;
  return texture_mesh(synth::icosphere(4, 1.02f), six_views_of_sphere(40.0), options, null_reporter());
}

// The colour of every unseen face's flat patch.
std::vector<Eigen::Vector3f> flat_colours(const TextureResult& result) {
  std::vector<Eigen::Vector3f> colours;
  const auto points = texture_points(result.mesh);
  for (std::size_t i = 0; i < points.size(); i += 4) {  // four points per triangle, the centroid first
    if (points[i].flat) colours.push_back(sample_atlas(result.mesh.atlases[points[i].page], points[i].uv));
  }
  return colours;
}

TEST(UnseenFaces, SphereSeenFromAboveGetsNoBackgroundColourBelow) {
  const TextureResult result = texture_sphere_seen_from_above(UnseenFaces::kDiffuse);
  ASSERT_GT(result.stats.num_unseen_faces, 100);
  const std::vector<Eigen::Vector3f> colours = flat_colours(result);
  ASSERT_EQ(static_cast<int>(colours.size()), result.stats.num_unseen_faces);
  float darkest = 255.0f;
  for (const Eigen::Vector3f& c : colours) darkest = std::min(darkest, c.minCoeff());
  std::cout << "[ figures  ] " << result.stats.num_unseen_faces << " unseen faces of " << result.stats.faces
            << ", darkest channel " << darkest << "\n";
  // Bound: the surface around them is never darker than the albedo's minimum;
  // a little below it for the mean of a face's pixels and 8-bit rounding.
  EXPECT_GT(darkest, kDarkestAlbedo - 8.0f);
}

TEST(UnseenFaces, GreyAndMarkModesColourEveryUnseenFaceAlike) {
  for (const auto& [mode, rgb] : {std::pair{UnseenFaces::kGrey, Eigen::Vector3f::Constant(kUnseenGrey).eval()},
                                  std::pair{UnseenFaces::kMark, Eigen::Vector3f(255.0f, 0.0f, 255.0f)}}) {
    const TextureResult result = texture_sphere_seen_from_above(mode);
    const std::vector<Eigen::Vector3f> colours = flat_colours(result);
    ASSERT_EQ(static_cast<int>(colours.size()), result.stats.num_unseen_faces);
    for (const Eigen::Vector3f& c : colours) EXPECT_LT((c - rgb).cwiseAbs().maxCoeff(), 1.5f);
  }
}

// A strip of 2 x n quads along x: faces 4k, 4k+1 (column k, bottom row) and
// 4k+2, 4k+3 (top row). Columns 0 and n-1 are seen, the rest not.
struct Strip {
  TriangleMesh mesh;
  int columns = 0;
  std::vector<int> faces_of_column(int k) const { return {4 * k, 4 * k + 1, 4 * k + 2, 4 * k + 3}; }
};

Strip make_strip(int columns) {
  Strip s;
  s.columns = columns;
  for (int x = 0; x <= columns; ++x) {
    for (int y = 0; y <= 2; ++y) s.mesh.vertices.emplace_back(static_cast<float>(x), static_cast<float>(y), 0.0f);
  }
  const auto v = [](int x, int y) { return 3 * x + y; };
  for (int x = 0; x < columns; ++x) {
    for (int y = 0; y < 2; ++y) {
      s.mesh.faces.emplace_back(v(x, y), v(x + 1, y), v(x + 1, y + 1));
      s.mesh.faces.emplace_back(v(x, y), v(x + 1, y + 1), v(x, y + 1));
    }
  }
  return s;
}

// One candidate per seen face, from view 0 at the given cosine.
FaceViewCandidates candidates_for(const std::vector<int>& labels, const std::vector<float>& cosine) {
  FaceViewCandidates c;
  c.offsets.push_back(0);
  for (std::size_t f = 0; f < labels.size(); ++f) {
    if (labels[f] >= 0) {
      FaceViewSample sample;
      sample.view = labels[f];
      sample.cos_angle = cosine[f];
      c.samples.push_back(sample);
    }
    c.offsets.push_back(static_cast<int>(c.samples.size()));
  }
  return c;
}

TEST(UnseenFaces, DiffusionInterpolatesBetweenTheSeenBordersAndSkipsGrazingFaces) {
  const Strip strip = make_strip(8);
  const int num_faces = static_cast<int>(strip.mesh.faces.size());
  std::vector<int> labels(num_faces, -1);
  std::vector<float> cosine(num_faces, 1.0f);
  std::vector<Eigen::Vector3f> seen(num_faces, Eigen::Vector3f::Zero());
  for (int f : strip.faces_of_column(0)) {
    labels[f] = 0;
    seen[f] = Eigen::Vector3f::Constant(200.0f);
  }
  for (int f : strip.faces_of_column(7)) {
    labels[f] = 0;
    seen[f] = Eigen::Vector3f::Constant(100.0f);
  }
  // Column 6 is seen edge-on and black (its pixels are background).
  for (int f : strip.faces_of_column(6)) {
    labels[f] = 0;
    cosine[f] = 0.05f;
  }
  const std::vector<FlatFace> flat = colour_unseen_faces(build_topology(strip.mesh), candidates_for(labels, cosine),
                                                         labels, seen, {}, UnseenFaces::kDiffuse);
  ASSERT_EQ(flat.size(), 20u);  // columns 1-5
  std::vector<float> column_mean(8, 0.0f);
  for (const FlatFace& face : flat) {
    EXPECT_GT(face.rgb.minCoeff(), 99.0f) << "face " << face.face;
    EXPECT_LT(face.rgb.maxCoeff(), 201.0f) << "face " << face.face;
    column_mean[face.face / 4] += face.rgb.x() / 4.0f;
  }
  // Harmonic along the strip: from 200 at column 0 down to 100 at column 7.
  for (int k = 1; k < 5; ++k) EXPECT_GT(column_mean[k], column_mean[k + 1] + 5.0f) << "column " << k;
}

TEST(UnseenFaces, UniformBackgroundIsFoundAndAFilledFrameIsNot) {
  std::vector<TextureView> views(2);
  views[0] = make_view(view_name(0), 0.0, 40.0, 3.5);
  render_sphere(views[0], 1.0);  // the sphere on black
  views[1] = views[0];
  views[1].image = cv::Mat(240, 320, CV_8UC3);
  cv::randu(views[1].image, cv::Scalar::all(0), cv::Scalar::all(255));  // a frame full of scene
  const std::vector<Eigen::Vector3f> gains = {Eigen::Vector3f::Constant(1.2f), Eigen::Vector3f::Ones()};
  const auto backgrounds = uniform_backgrounds(views, gains);
  ASSERT_EQ(backgrounds.size(), 2u);
  ASSERT_TRUE(backgrounds[0].has_value());
  EXPECT_LT(backgrounds[0]->norm(), 1.0f);
  EXPECT_FALSE(backgrounds[1].has_value());
}

// A face seen well whose colour is its photo's background is no source.
TEST(UnseenFaces, FacesShowingTheBackgroundAreNoSource) {
  const Strip strip = make_strip(6);
  const int num_faces = static_cast<int>(strip.mesh.faces.size());
  std::vector<int> labels(num_faces, -1);
  std::vector<Eigen::Vector3f> seen(num_faces, Eigen::Vector3f::Zero());
  for (int f : strip.faces_of_column(0)) {
    labels[f] = 0;
    seen[f] = Eigen::Vector3f(150.0f, 120.0f, 90.0f);
  }
  for (int f : strip.faces_of_column(1)) labels[f] = 0;  // black: the background
  FaceViewCandidates candidates = candidates_for(labels, std::vector<float>(num_faces, 1.0f));
  for (FaceViewSample& sample : candidates.samples) sample.mean_rgb = seen[0];
  for (int f : strip.faces_of_column(1)) candidates.samples[candidates.begin(f)].mean_rgb.setZero();
  const std::vector<FlatFace> flat = colour_unseen_faces(build_topology(strip.mesh), candidates, labels, seen,
                                                         {Eigen::Vector3f::Zero()}, UnseenFaces::kDiffuse);
  ASSERT_EQ(flat.size(), 16u);  // columns 2-5
  for (const FlatFace& face : flat) EXPECT_LT((face.rgb - seen[0]).norm(), 1.0f) << "face " << face.face;
}

TEST(UnseenFaces, PieceNoViewSeesIsGrey) {
  const Strip strip = make_strip(3);
  const int num_faces = static_cast<int>(strip.mesh.faces.size());
  const std::vector<int> labels(num_faces, -1);
  const std::vector<Eigen::Vector3f> seen(num_faces, Eigen::Vector3f::Zero());
  const std::vector<FlatFace> flat =
      colour_unseen_faces(build_topology(strip.mesh), candidates_for(labels, std::vector<float>(num_faces, 1.0f)),
                          labels, seen, {}, UnseenFaces::kDiffuse);
  ASSERT_EQ(static_cast<int>(flat.size()), num_faces);
  for (const FlatFace& face : flat) EXPECT_EQ(face.rgb, Eigen::Vector3f::Constant(kUnseenGrey));
}

}  // namespace
}  // namespace hos::texture
