#include "eval/self_intersection.h"

#include <gtest/gtest.h>

#include "synth/shapes.h"

namespace hos::eval {
namespace {

TriangleMesh two_triangles(const Eigen::Vector3f& shift) {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};  // in the plane z = 0
  for (const Eigen::Vector3f& p :
       {Eigen::Vector3f(0.5f, 0.5f, -1), Eigen::Vector3f(0.5f, 0.5f, 1), Eigen::Vector3f(0.5f, 1.5f, 1)}) {
    mesh.vertices.push_back(p + shift);
  }
  mesh.faces = {{0, 1, 2}, {3, 4, 5}};
  return mesh;
}

TEST(SelfIntersection, CrossingTrianglesCountAndSeparateOnesDoNot) {
  EXPECT_EQ(count_self_intersections(two_triangles(Eigen::Vector3f::Zero())), 1u);
  EXPECT_EQ(count_self_intersections(two_triangles(Eigen::Vector3f(5, 0, 0))), 0u);
  EXPECT_EQ(count_self_intersections(two_triangles(Eigen::Vector3f(0, 0, 1.5f))), 0u);  // above the plane
}

TEST(SelfIntersection, AClosedSphereHasNoneAndOverlappingSpheresDo) {
  const TriangleMesh sphere = synth::icosphere(3);
  EXPECT_EQ(count_self_intersections(sphere), 0u);
  TriangleMesh two = sphere;
  const int offset = static_cast<int>(two.vertices.size());
  for (const Eigen::Vector3f& v : sphere.vertices) two.vertices.push_back(v + Eigen::Vector3f(1.0f, 0.0f, 0.0f));
  for (const Eigen::Vector3i& f : sphere.faces) two.faces.push_back(f + Eigen::Vector3i::Constant(offset));
  // Two unit spheres one radius apart cross along a circle of radius 0.87:
  // about 2 pi 0.87 / (edge 0.14) crossings or more.
  EXPECT_GT(count_self_intersections(two), 30u);
  for (std::size_t v = offset; v < two.vertices.size(); ++v) two.vertices[v].x() += 2.0f;
  EXPECT_EQ(count_self_intersections(two), 0u);
}

TEST(SelfIntersection, AVertexPushedThroughTheOtherSideIsFound) {
  TriangleMesh sphere = synth::icosphere(3);
  // The vertex nearest +z, pulled down through the sphere to below z = -1
  // (off the axis: on it, its edges would meet the bottom fan's edges exactly,
  // which counts as touching).
  std::size_t top = 0;
  for (std::size_t v = 0; v < sphere.vertices.size(); ++v) {
    if (sphere.vertices[v].z() > sphere.vertices[top].z()) top = v;
  }
  sphere.vertices[top] = Eigen::Vector3f(0.05f, 0.03f, -1.5f);
  EXPECT_GT(count_self_intersections(sphere), 0u);
}

}  // namespace
}  // namespace hos::eval
