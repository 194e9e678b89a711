#include "eval/mesh_sanity.h"

#include <gtest/gtest.h>

#include "synth/shapes.h"
#include "tests/eval/test_meshes.h"

namespace hos::eval {
namespace {

TEST(MeshSanity, ClosedSphereIsWatertightGenusZero) {
  const TriangleMesh mesh = synth::icosphere(2, 1.0);
  const MeshSanity s = check_mesh_sanity(mesh);
  EXPECT_TRUE(s.watertight);
  EXPECT_TRUE(s.edge_manifold);
  EXPECT_TRUE(s.vertex_manifold);
  EXPECT_TRUE(s.consistently_oriented);
  EXPECT_EQ(s.components, 1u);
  EXPECT_EQ(s.euler_characteristic, 2);
  ASSERT_TRUE(s.genus.has_value());
  EXPECT_EQ(*s.genus, 0);
  EXPECT_EQ(s.degenerate_faces, 0u);
  EXPECT_EQ(s.edges, 3 * mesh.faces.size() / 2);
}

TEST(MeshSanity, HoleIsNotWatertight) {
  TriangleMesh mesh = synth::icosphere(2, 1.0);
  mesh.faces.pop_back();
  const MeshSanity s = check_mesh_sanity(mesh);
  EXPECT_FALSE(s.watertight);
  EXPECT_EQ(s.boundary_edges, 3u);
  EXPECT_EQ(s.euler_characteristic, 1);
  EXPECT_FALSE(s.genus.has_value());
}

TEST(MeshSanity, NonManifoldEdgeIsReported) {
  TriangleMesh mesh = synth::icosphere(1, 1.0);
  // A fin: a third face on the edge of face 0.
  const Eigen::Vector3i f = mesh.faces[0];
  mesh.vertices.push_back(Eigen::Vector3f(3, 3, 3));
  mesh.faces.push_back({f[0], f[1], static_cast<int>(mesh.vertices.size()) - 1});
  const MeshSanity s = check_mesh_sanity(mesh);
  EXPECT_EQ(s.non_manifold_edges, 1u);
  EXPECT_FALSE(s.edge_manifold);
  EXPECT_FALSE(s.watertight);
}

TEST(MeshSanity, TwoSpheresTouchingAtAVertexAreNotVertexManifold) {
  TriangleMesh a = synth::icosphere(1, 1.0);
  const TriangleMesh b = synth::icosphere(1, 1.0, Eigen::Vector3f(2, 0, 0));
  // Glue b's vertex nearest to a's vertex 0 onto it: one shared vertex, two fans.
  const int offset = static_cast<int>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (Eigen::Vector3i f : b.faces) {
    for (int c = 0; c < 3; ++c) f[c] = f[c] == 0 ? 0 : f[c] + offset;
    a.faces.push_back(f);
  }
  const MeshSanity s = check_mesh_sanity(a);
  EXPECT_TRUE(s.edge_manifold);
  EXPECT_EQ(s.non_manifold_vertices, 1u);
  EXPECT_FALSE(s.vertex_manifold);
  EXPECT_EQ(s.components, 1u);
  EXPECT_EQ(s.unreferenced_vertices, 1u);  // b's own vertex 0
}

TEST(MeshSanity, FlippedFaceAndDegenerateFaceAreReported) {
  TriangleMesh mesh = testing::cube(1.0f, Eigen::Vector3f::Zero(), 2);
  std::swap(mesh.faces[0][1], mesh.faces[0][2]);
  // A separate zero-area face on three collinear vertices.
  const int n = static_cast<int>(mesh.vertices.size());
  for (int i = 0; i < 3; ++i) mesh.vertices.emplace_back(5.0f + i, 0.0f, 0.0f);
  mesh.faces.push_back({n, n + 1, n + 2});
  const MeshSanity s = check_mesh_sanity(mesh);
  EXPECT_EQ(s.inconsistent_edges, 3u);
  EXPECT_FALSE(s.consistently_oriented);
  EXPECT_EQ(s.degenerate_faces, 1u);
}

TEST(MeshSanity, TwoComponentsAndTorusGenus) {
  TriangleMesh mesh = testing::cube(1.0f, Eigen::Vector3f::Zero());
  const TriangleMesh other = testing::cube(1.0f, Eigen::Vector3f(5, 0, 0));
  const int offset = static_cast<int>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const Eigen::Vector3i& f : other.faces) mesh.faces.push_back(f + Eigen::Vector3i::Constant(offset));
  const MeshSanity s = check_mesh_sanity(mesh);
  EXPECT_EQ(s.components, 2u);
  EXPECT_EQ(s.euler_characteristic, 4);
  EXPECT_EQ(*s.genus, 0);

  // A torus as an n x m grid with wrap-around: chi = 0, genus 1.
  TriangleMesh torus;
  const int n = 12, m = 8;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / m;
      torus.vertices.emplace_back((2 + std::cos(v)) * std::cos(u), (2 + std::cos(v)) * std::sin(u), std::sin(v));
    }
  }
  auto id = [&](int i, int j) { return ((i + n) % n) * m + (j + m) % m; };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      torus.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      torus.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  const MeshSanity t = check_mesh_sanity(torus);
  EXPECT_TRUE(t.watertight);
  EXPECT_EQ(t.euler_characteristic, 0);
  EXPECT_EQ(*t.genus, 1);
}

}  // namespace
}  // namespace hos::eval
