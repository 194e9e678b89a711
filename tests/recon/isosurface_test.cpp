// recon/isosurface.*: a sampled signed distance gives a closed, outward
// oriented, accurate surface.
#include "recon/isosurface.h"

#include <gtest/gtest.h>

#include "tests/recon/shape_samples.h"

namespace hos::recon {
namespace {

TEST(Isosurface, SphereDistanceFieldGivesAClosedAccurateSurface) {
  GridGeometry g;
  g.dims = Eigen::Vector3i::Constant(31);
  g.spacing = 0.1;
  g.origin = Eigen::Vector3d::Constant(-1.5);
  ScalarGrid f(g);
  for (int k = 0; k < 31; ++k)
    for (int j = 0; j < 31; ++j)
      for (int i = 0; i < 31; ++i) f.values[g.index(i, j, k)] = g.position(i, j, k).norm() - 0.97;
  const TriangleMesh mesh = extract_isosurface(f, 0.0);
  const auto t = testing::analyze_topology(mesh);
  EXPECT_TRUE(t.watertight());
  EXPECT_EQ(t.misoriented_edges, 0u);
  EXPECT_EQ(t.euler(), 2);
  EXPECT_EQ(t.components, 1);
  EXPECT_GT(testing::signed_volume(mesh), 0.0);
  const double volume = 4.0 / 3.0 * M_PI * std::pow(0.97, 3);
  EXPECT_NEAR(testing::signed_volume(mesh), volume, 0.03 * volume);
  for (const auto& v : mesh.vertices) EXPECT_NEAR(v.norm(), 0.97, 0.01);
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) {
    EXPECT_GT(mesh.normals[i].dot(mesh.vertices[i].normalized()), 0.9f);
  }
}

TEST(Isosurface, SurfaceClosesAtTheDomainBoundary) {
  // f below the isovalue everywhere inside: the ghost ring (0) closes it.
  GridGeometry g;
  g.dims = Eigen::Vector3i(5, 6, 7);
  ScalarGrid f(g);
  for (double& v : f.values) v = -1.0;
  const TriangleMesh mesh = extract_isosurface(f, -0.5);
  const auto t = testing::analyze_topology(mesh);
  EXPECT_TRUE(t.watertight());
  EXPECT_EQ(t.euler(), 2);
}

}  // namespace
}  // namespace hos::recon
