#include "eval/curvature.h"

#include <gtest/gtest.h>

#include <cmath>

#include "synth/shapes.h"
#include "tests/eval/test_meshes.h"

namespace hos::eval {
namespace {

// Sphere of radius r = 2 as a level-4 icosphere (5120 faces, 2562 vertices).
// Tolerances: every vertex within 3% of 1/r and 6% of 1/r^2 (the 12 valence-5
// vertices of the icosahedron are the worst); the averages within 0.5% / 1%.
TEST(Curvature, SphereMeanAndGaussian) {
  const double r = 2.0;
  const TriangleMesh mesh = synth::icosphere(4, r);
  const VertexCurvature c = compute_vertex_curvature(mesh);
  double sum_h = 0.0, sum_k = 0.0;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    ASSERT_TRUE(c.defined[i]) << i;
    EXPECT_NEAR(c.mean[i], 1.0 / r, 0.03 / r) << i;  // positive: convex, outward normals
    EXPECT_NEAR(c.gaussian[i], 1.0 / (r * r), 0.06 / (r * r)) << i;
    sum_h += c.mean[i];
    sum_k += c.gaussian[i];
  }
  const double n = static_cast<double>(mesh.vertices.size());
  EXPECT_NEAR(sum_h / n, 1.0 / r, 0.005 / r);
  EXPECT_NEAR(sum_k / n, 1.0 / (r * r), 0.01 / (r * r));
  // Gauss-Bonnet: the angle defects of a closed genus-0 surface add up to 4 pi.
  double total_defect = 0.0;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) total_defect += c.gaussian[i] * c.mixed_area[i];
  EXPECT_NEAR(total_defect, 4.0 * M_PI, 1e-9);
}

TEST(Curvature, PlaneIsFlatAndBoundaryIsSkipped) {
  // A subdivided cube side: interior vertices of a flat side have H = K = 0.
  const TriangleMesh cube = testing::cube(1.0f, Eigen::Vector3f::Zero(), 4);
  TriangleMesh side;
  side.vertices = cube.vertices;
  for (std::size_t f = 0; f < 32; ++f) side.faces.push_back(cube.faces[f]);  // first side: 4x4x2 faces
  const VertexCurvature c = compute_vertex_curvature(side);
  int interior = 0;
  for (std::size_t i = 0; i < side.vertices.size(); ++i) {
    if (!c.defined[i]) continue;
    ++interior;
    EXPECT_NEAR(c.mean[i], 0.0, 1e-6);
    EXPECT_NEAR(c.gaussian[i], 0.0, 1e-6);
  }
  EXPECT_EQ(interior, 9);  // the 3x3 interior grid vertices
}

TEST(CurvatureStats, TableOneFigures) {
  const double r = 1.5;
  const TriangleMesh mesh = synth::icosphere(4, r);
  std::vector<Eigen::Vector3f> points;
  for (const auto& v : mesh.vertices) points.push_back(v * 1.01f);  // 1% outside: distance 0.015 at vertices
  const CurvatureStats s = compute_curvature_stats(mesh, &points, null_reporter());
  EXPECT_EQ(s.triangles, 5120u);
  EXPECT_EQ(s.vertices_measured, mesh.vertices.size());
  EXPECT_NEAR(s.mean_abs_h, 1.0 / r, 0.005 / r);
  EXPECT_NEAR(s.max_abs_h, 1.0 / r, 0.03 / r);
  EXPECT_NEAR(s.mean_abs_k, 1.0 / (r * r), 0.01 / (r * r));
  // A sphere is evenly curved: the 99th percentiles lie between mean and max.
  EXPECT_NEAR(s.p99_abs_h, 1.0 / r, 0.03 / r);
  EXPECT_NEAR(s.p99_abs_k, 1.0 / (r * r), 0.05 / (r * r));
  EXPECT_LE(s.p99_abs_h, s.max_abs_h);
  EXPECT_LE(s.p99_abs_k, s.max_abs_k);
  ASSERT_TRUE(s.rms_point_distance.has_value());
  EXPECT_NEAR(*s.rms_point_distance, 0.01 * r, 1e-5);
  EXPECT_FALSE(compute_curvature_stats(mesh, nullptr, null_reporter()).rms_point_distance.has_value());
}

// One vertex pulled out of the sphere: a spike that sets the maxima but
// touches 7 of 2562 vertices, fewer than the top 1%, so the 99th percentiles
// stay the sphere's.
TEST(CurvatureStats, PercentilesIgnoreASingleSpike) {
  const double r = 1.5;
  TriangleMesh mesh = synth::icosphere(4, r);
  mesh.vertices[0] *= 1.2f;
  const CurvatureStats s = compute_curvature_stats(mesh, nullptr, null_reporter());
  EXPECT_GT(s.max_abs_h, 3.0 / r);
  EXPECT_GT(s.max_abs_k, 10.0 / (r * r));
  EXPECT_NEAR(s.p99_abs_h, 1.0 / r, 0.03 / r);
  EXPECT_NEAR(s.p99_abs_k, 1.0 / (r * r), 0.05 / (r * r));
}

}  // namespace
}  // namespace hos::eval
