#include "eval/triangle_tree.h"

#include <gtest/gtest.h>

#include <random>

#include "synth/shapes.h"
#include "tests/eval/test_meshes.h"

namespace hos::eval {
namespace {

TEST(ClosestPointOnTriangle, RegionsOfAUnitTriangle) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_LT((closest_point_on_triangle({0.2, 0.2, 3}, a, b, c) - Eigen::Vector3d(0.2, 0.2, 0)).norm(), 1e-12);
  EXPECT_LT((closest_point_on_triangle({-1, -1, 0}, a, b, c) - a).norm(), 1e-12);
  EXPECT_LT((closest_point_on_triangle({2, -1, 1}, a, b, c) - b).norm(), 1e-12);
  EXPECT_LT((closest_point_on_triangle({0.5, -2, 0}, a, b, c) - Eigen::Vector3d(0.5, 0, 0)).norm(), 1e-12);
  EXPECT_LT((closest_point_on_triangle({1, 1, 0}, a, b, c) - Eigen::Vector3d(0.5, 0.5, 0)).norm(), 1e-12);
}

TEST(TriangleTree, MatchesBruteForce) {
  const TriangleMesh mesh = synth::icosphere(3, 1.0);
  const TriangleTree tree(mesh);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int q = 0; q < 300; ++q) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    double brute = std::numeric_limits<double>::infinity();
    for (const auto& f : mesh.faces) {
      const Eigen::Vector3d x =
          closest_point_on_triangle(p, mesh.vertices[f[0]].cast<double>(), mesh.vertices[f[1]].cast<double>(),
                                    mesh.vertices[f[2]].cast<double>());
      brute = std::min(brute, (p - x).norm());
    }
    EXPECT_NEAR(tree.nearest(p).distance, brute, 1e-12);
  }
}

}  // namespace
}  // namespace hos::eval
