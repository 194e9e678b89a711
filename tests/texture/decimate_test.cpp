#include "texture/decimate.h"

#include <gtest/gtest.h>

#include "synth/shapes.h"
#include "tests/texture/scene_fixtures.h"

namespace hos::texture {
namespace {

TEST(Decimate, ReachesTheBudgetAndKeepsTheShape) {
  const TriangleMesh sphere = synth::icosphere(5, 1.0);  // 20480 faces
  DecimationStats stats;
  const TriangleMesh small = decimate_mesh(sphere, 2000, &stats);
  EXPECT_LE(small.faces.size(), 2000u);
  EXPECT_GT(small.faces.size(), 1000u);
  EXPECT_EQ(stats.faces_before, sphere.faces.size());
  EXPECT_EQ(stats.faces_after, small.faces.size());
  EXPECT_NO_THROW(small.check_consistent());
  // Vertices are a subset of the input's: still on the unit sphere.
  for (const auto& v : small.vertices) EXPECT_NEAR(v.norm(), 1.0f, 1e-5f);
  // Face centroids stay close to the sphere (the shape is kept).
  for (const auto& f : small.faces) {
    const Eigen::Vector3f c = (small.vertices[f[0]] + small.vertices[f[1]] + small.vertices[f[2]]) / 3.0f;
    EXPECT_GT(c.norm(), 0.95f);
  }
}

TEST(Decimate, SmallMeshIsReturnedUnchanged) {
  const TriangleMesh sphere = synth::icosphere(2, 1.0);
  const TriangleMesh same = decimate_mesh(sphere, 100000);
  EXPECT_EQ(same.faces, sphere.faces);
  EXPECT_EQ(same.vertices.size(), sphere.vertices.size());
}

}  // namespace
}  // namespace hos::texture
