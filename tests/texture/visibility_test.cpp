#include "texture/visibility.h"

#include <gtest/gtest.h>

#include "synth/shapes.h"
#include "tests/texture/scene_fixtures.h"

namespace hos::texture {
namespace {

bool sees(const FaceViewCandidates& c, int face, int view) {
  for (int i = c.begin(face); i < c.end(face); ++i) {
    if (c.samples[i].view == view) return true;
  }
  return false;
}

// A unit sphere at the origin and a small sphere between it and the camera:
// faces of the big sphere behind the small one are occluded (depth test),
// faces on the far side are back-facing.
TEST(Visibility, DepthBufferHidesOccludedFaces) {
  TriangleMesh mesh = synth::icosphere(4, 1.0);
  const TriangleMesh ball = synth::icosphere(3, 0.3);
  const int big_faces = static_cast<int>(mesh.faces.size());
  const int offset = static_cast<int>(mesh.vertices.size());
  for (const auto& v : ball.vertices) mesh.vertices.push_back(v + Eigen::Vector3f(1.8f, 0.0f, 0.0f));
  for (const auto& f : ball.faces) mesh.faces.push_back(f + Eigen::Vector3i::Constant(offset));
  std::vector<TextureView> views = {testing::make_view("front", 0.0, 0.0, 4.0)};
  views[0].image = cv::Mat(240, 320, CV_8UC3, cv::Scalar(50, 100, 150));
  const MeshTopology topology = build_topology(mesh);
  const FaceViewCandidates c = compute_visibility(mesh, topology, views, TextureOptions{}, null_reporter());
  const Eigen::Vector3d camera = views[0].pose.center();
  int occluded = 0, visible = 0;
  for (int f = 0; f < big_faces; ++f) {
    const Eigen::Vector3f centroid =
        (mesh.vertices[mesh.faces[f][0]] + mesh.vertices[mesh.faces[f][1]] + mesh.vertices[mesh.faces[f][2]]) / 3.0f;
    // Analytic truth: does the segment camera -> centroid pass through the ball?
    const Eigen::Vector3d p = centroid.cast<double>(), ball_center(1.8, 0, 0);
    const Eigen::Vector3d d = (p - camera).normalized();
    const double t = std::clamp((ball_center - camera).dot(d), 0.0, (p - camera).norm());
    const double miss = (camera + t * d - ball_center).norm();
    const double cos_angle = topology.face_normals[f].cast<double>().dot((camera - p).normalized());
    if (cos_angle < 0.1) {  // beyond the 80 degree limit or back-facing
      EXPECT_FALSE(sees(c, f, 0)) << "grazing or back-facing face " << f;
    } else if (cos_angle < 0.3) {
      continue;
    } else if (miss < 0.27) {
      EXPECT_FALSE(sees(c, f, 0)) << "face " << f << " is behind the ball";
      ++occluded;
    } else if (miss > 0.33) {
      EXPECT_TRUE(sees(c, f, 0)) << "face " << f << " is in plain view";
      ++visible;
    }
  }
  EXPECT_GT(occluded, 50);
  EXPECT_GT(visible, 500);
  // The sample's colour is the photo's.
  for (int f = 0; f < big_faces; ++f) {
    for (int i = c.begin(f); i < c.end(f); ++i) {
      EXPECT_NEAR(c.samples[i].mean_rgb.x(), 150.0f, 1.0f);
      EXPECT_NEAR(c.samples[i].mean_rgb.z(), 50.0f, 1.0f);
    }
  }
}

}  // namespace
}  // namespace hos::texture
