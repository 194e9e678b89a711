#include "texture/decimate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <optional>

#include "synth/shapes.h"
#include "tests/texture/scene_fixtures.h"

namespace hos::texture {
namespace {

TEST(Decimate, ReachesTheBudgetAndKeepsTheShape) {
  const TriangleMesh sphere = synth::icosphere(5, 1.0);  // 20480 faces
  DecimationStats stats;
  const TriangleMesh small = decimate_mesh(sphere, 2000, 0.0, &stats);
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

// A height field over [0, 1]^2 on an n x n vertex grid: flat where x < 0.5,
// bumps of the given amplitude (period 0.25) where x >= 0.5.
float half_bumpy_height(float x, float y, float amplitude) {
  if (x < 0.5f) return 0.0f;
  const float pi = 3.14159265f;
  return amplitude * std::sin(8.0f * pi * (x - 0.5f)) * std::sin(8.0f * pi * y);
}

TriangleMesh half_bumpy_grid(int n, float amplitude) {
  return synth::grid_mesh(n, 1.0f / static_cast<float>(n - 1),
                          [amplitude](float x, float y) { return half_bumpy_height(x, y, amplitude); });
}

// Height of the decimated surface above (x, y): the triangle whose xy
// projection holds the point (a height field stays one after collapses).
std::optional<float> surface_height(const TriangleMesh& mesh, float x, float y) {
  for (const auto& f : mesh.faces) {
    const Eigen::Vector3f& a = mesh.vertices[f[0]];
    const Eigen::Vector3f& b = mesh.vertices[f[1]];
    const Eigen::Vector3f& c = mesh.vertices[f[2]];
    const float det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (std::abs(det) < 1e-12f) continue;
    const float u = ((x - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (y - a.y())) / det;
    const float v = ((b.x() - a.x()) * (y - a.y()) - (x - a.x()) * (b.y() - a.y())) / det;
    constexpr float kEps = 1e-5f;
    if (u < -kEps || v < -kEps || u + v > 1.0f + kEps) continue;
    return a.z() + u * (b.z() - a.z()) + v * (c.z() - a.z());
  }
  return std::nullopt;
}

TEST(Decimate, AnErrorBoundCollapsesFlatPartsAndKeepsShapeWithinIt) {
  const float amplitude = 0.02f;
  const TriangleMesh grid = half_bumpy_grid(81, amplitude);  // 12800 faces
  for (const double bound : {2e-4, 1e-3}) {
    DecimationStats stats;
    const TriangleMesh small = decimate_mesh(grid, 0, bound, &stats);
    EXPECT_NO_THROW(small.check_consistent());
    EXPECT_EQ(stats.faces_after, small.faces.size());
    // The flat half (6400 faces) needs a handful; the bumps keep most of theirs.
    EXPECT_LT(small.faces.size(), grid.faces.size() * 3 / 4) << bound;
    EXPECT_GT(small.faces.size(), grid.faces.size() / 20) << bound;
    float worst = 0.0f;
    for (const auto& v : grid.vertices) {
      const std::optional<float> z = surface_height(small, v.x(), v.y());
      ASSERT_TRUE(z.has_value()) << v.transpose();
      worst = std::max(worst, std::abs(*z - v.z()));
    }
    std::cout << "[ figures  ] bound " << bound << ": " << grid.faces.size() << " -> " << small.faces.size()
              << " faces, largest height error " << worst << "\n";
    // The bound is on meshoptimizer's quadric error (the distance to the
    // planes of the merged faces, accumulated), not on the distance to the
    // new surface: 1.5x and 2.8x the bound here.
    EXPECT_LE(worst, 3.0 * bound);
  }
  // A tighter bound keeps more faces.
  EXPECT_GT(decimate_mesh(grid, 0, 2e-4).faces.size(), decimate_mesh(grid, 0, 1e-3).faces.size());
}

TEST(Decimate, NeitherBudgetNorBoundKeepsTheMesh) {
  const TriangleMesh grid = half_bumpy_grid(9, 0.02f);
  EXPECT_EQ(decimate_mesh(grid, 0, 0.0).faces, grid.faces);
}

TEST(Decimate, FinestPixelSizeIsTheNearestDepthOverTheFocalLength) {
  // Vertices on the optical axis of a camera at the origin looking down +z
  // (focal 500 px), at depths 1..10; one behind it, one outside its frame.
  SamplingCamera camera{Camera::pinhole(1, 640, 480, 500.0, 400.0, 320.0, 240.0), ImageRecord{}};
  TriangleMesh mesh;
  for (int d = 1; d <= 10; ++d) mesh.vertices.emplace_back(0.0f, 0.0f, static_cast<float>(d));
  mesh.vertices.emplace_back(0.0f, 0.0f, -0.5f);  // behind
  mesh.vertices.emplace_back(5.0f, 0.0f, 0.5f);   // projects to x = 5320 px
  EXPECT_DOUBLE_EQ(finest_pixel_size(mesh, {camera}, 0.0), 1.0 / 500.0);
  EXPECT_DOUBLE_EQ(finest_pixel_size(mesh, {camera}, 1.0), 10.0 / 500.0);
  // A second camera twice as close to the far vertices samples them finer.
  SamplingCamera closer = camera;
  closer.pose.cam_from_world_translation = Eigen::Vector3d(0.0, 0.0, -5.0);  // centre at z = 5
  EXPECT_DOUBLE_EQ(finest_pixel_size(mesh, {camera, closer}, 1.0), 5.0 / 500.0);
  // No vertex in front of a camera: no size.
  TriangleMesh behind;
  behind.vertices.emplace_back(0.0f, 0.0f, -1.0f);
  EXPECT_EQ(finest_pixel_size(behind, {camera}), 0.0);
}

TEST(Decimate, SmallMeshIsReturnedUnchanged) {
  const TriangleMesh sphere = synth::icosphere(2, 1.0);
  const TriangleMesh same = decimate_mesh(sphere, 100000, 0.0);
  EXPECT_EQ(same.faces, sphere.faces);
  EXPECT_EQ(same.vertices.size(), sphere.vertices.size());
}

}  // namespace
}  // namespace hos::texture
