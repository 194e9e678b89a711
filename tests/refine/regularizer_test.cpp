// The regulariser alone (no photometric targets): the thin-plate energy
// leaves a smooth closed surface nearly where it is, the membrane energy
// shrinks it (Pan & Skala's argument for eq. (3) over eq. (1), on the surface).
#include "refine/regularizer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "tests/refine/rock_fixture.h"

namespace hos::refine {
namespace {

// Five rounds of the linear step without targets; returns the volume ratio.
double volume_ratio_after_rounds(const TriangleMesh& input, Regularizer regularizer) {
  RefineOptions options;
  options.regularizer = regularizer;
  TriangleMesh mesh = input;
  const VertexRings rings = vertex_rings(mesh);
  const std::vector<VertexTarget> none(mesh.vertices.size());
  for (int round = 0; round < 5; ++round) {
    const std::vector<Eigen::Vector3f> normals = vertex_normals(mesh);
    const std::vector<float> s = solve_displacements(mesh, rings, normals, none, 1.0, options);
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) mesh.vertices[v] += s[v] * normals[v];
  }
  return testing::enclosed_volume(mesh) / testing::enclosed_volume(input);
}

TEST(Regularizer, ThinPlateKeepsTheVolumeWhereMembraneShrinks) {
  const TriangleMesh rock = testing::smoothed(testing::rock_truth(), 10);
  const double thin_plate = volume_ratio_after_rounds(rock, Regularizer::kThinPlate);
  const double membrane = volume_ratio_after_rounds(rock, Regularizer::kMembrane);
  std::cout << "[ figures  ] volume after 5 rounds without data: thin plate " << thin_plate << ", membrane " << membrane
            << "\n";
  EXPECT_NEAR(thin_plate, 1.0, 0.005);
  EXPECT_LT(membrane, 1.0 - 4.0 * std::abs(1.0 - thin_plate));
}

TEST(Regularizer, FollowsExactTargetsWithoutRegularisation) {
  const TriangleMesh rock = testing::rock_truth();
  RefineOptions options;
  options.lambda = 0.0;
  std::vector<VertexTarget> targets(rock.vertices.size());
  for (std::size_t v = 0; v < targets.size(); ++v) targets[v] = {0.01f * std::sin(static_cast<float>(v)), 1.0f, 1.0f};
  const std::vector<float> s =
      solve_displacements(rock, vertex_rings(rock), vertex_normals(rock), targets, 1.0, options);
  for (std::size_t v = 0; v < s.size(); ++v) {
    // w / (w + anchor) of the target.
    ASSERT_NEAR(s[v], targets[v].offset / (1.0 + options.anchor_weight), 1e-6f) << v;
  }
}

}  // namespace
}  // namespace hos::refine
