#include "render/depth_buffer.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hos::render {
namespace {

// A square of two faces spanning pixels [x0, x1] x [y0, y1] at depth z,
// appended to mesh and to its projection.
void add_square(
    TriangleMesh& mesh, std::vector<Eigen::Vector3f>& projected, float x0, float x1, float y0, float y1, float z) {
  const int base = static_cast<int>(mesh.vertices.size());
  for (const Eigen::Vector3f& p : {Eigen::Vector3f(x0, y0, z), Eigen::Vector3f(x1, y0, z), Eigen::Vector3f(x1, y1, z),
                                   Eigen::Vector3f(x0, y1, z)}) {
    mesh.vertices.push_back(p);  // the world positions play no part
    projected.push_back(p);
  }
  mesh.faces.emplace_back(base, base + 1, base + 2);
  mesh.faces.emplace_back(base, base + 2, base + 3);
}

TEST(DepthBuffer, NearestFaceWinsAndEmptyPixelsAreInfinite) {
  TriangleMesh mesh;
  std::vector<Eigen::Vector3f> projected;
  add_square(mesh, projected, 2.0f, 12.0f, 2.0f, 12.0f, 3.0f);  // faces 0, 1: far
  add_square(mesh, projected, 6.0f, 16.0f, 6.0f, 16.0f, 2.0f);  // faces 2, 3: near, overlapping
  const DepthBuffer buffer = rasterize_depth(mesh, projected, 20, 20);
  ASSERT_EQ(buffer.depth.size(), cv::Size(20, 20));
  // Pixel (x, y) has its centre at (x + 0.5, y + 0.5).
  EXPECT_FLOAT_EQ(buffer.depth.at<float>(3, 3), 3.0f);
  EXPECT_LE(buffer.face_id.at<int>(3, 3), 1);
  EXPECT_FLOAT_EQ(buffer.depth.at<float>(8, 8), 2.0f);  // both squares: the near one
  EXPECT_GE(buffer.face_id.at<int>(8, 8), 2);
  EXPECT_FLOAT_EQ(buffer.depth.at<float>(14, 14), 2.0f);
  EXPECT_TRUE(std::isinf(buffer.depth.at<float>(0, 0)));
  EXPECT_EQ(buffer.face_id.at<int>(0, 0), -1);
  EXPECT_TRUE(std::isinf(buffer.depth.at<float>(18, 3)));
  // Every pixel centre inside the union is covered exactly once by the depth test.
  int covered = 0;
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 20; ++x) covered += buffer.face_id.at<int>(y, x) >= 0;
  }
  EXPECT_EQ(covered, 10 * 10 + 10 * 10 - 6 * 6);
}

TEST(DepthBuffer, DepthIsPerspectiveCorrectOnASlantedFace) {
  // A face whose corners lie at depths 1 and 3: depth along it is not affine
  // in the image, 1/depth is.
  TriangleMesh mesh;
  std::vector<Eigen::Vector3f> projected = {{0.0f, 0.0f, 1.0f}, {10.0f, 0.0f, 3.0f}, {0.0f, 10.0f, 1.0f}};
  mesh.vertices = projected;
  mesh.faces.emplace_back(0, 1, 2);
  const DepthBuffer buffer = rasterize_depth(mesh, projected, 10, 10);
  // At pixel centre x = 5.5: 1/z = 1 + (5.5 / 10) * (1/3 - 1).
  const float expected = 1.0f / (1.0f + 0.55f * (1.0f / 3.0f - 1.0f));
  EXPECT_NEAR(buffer.depth.at<float>(0, 5), expected, 1e-5f);
}

TEST(DepthBuffer, FacesBehindTheCameraAreSkipped) {
  TriangleMesh mesh;
  std::vector<Eigen::Vector3f> projected = {{0.0f, 0.0f, -1.0f}, {10.0f, 0.0f, 2.0f}, {0.0f, 10.0f, 2.0f}};
  mesh.vertices = projected;
  mesh.faces.emplace_back(0, 1, 2);
  const DepthBuffer buffer = rasterize_depth(mesh, projected, 10, 10);
  EXPECT_EQ(cv::countNonZero(buffer.face_id >= 0), 0);
}

}  // namespace
}  // namespace hos::render
