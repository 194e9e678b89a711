#include "refine/edge_split.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <limits>
#include <set>

#include "eval/mesh_sanity.h"
#include "refine/mesh_geometry.h"
#include "synth/shapes.h"
#include "tests/refine/rock_fixture.h"

namespace hos::refine {
namespace {

constexpr float kNever = std::numeric_limits<float>::infinity();

void expect_closed_manifold(const TriangleMesh& mesh) {
  const eval::MeshSanity sanity = eval::check_mesh_sanity(mesh);
  EXPECT_TRUE(sanity.watertight) << "an edge without two faces: a hanging vertex";
  EXPECT_TRUE(sanity.vertex_manifold);
  EXPECT_TRUE(sanity.consistently_oriented);
}

TEST(EdgeSplit, ShortLimitSplitsEveryFaceIntoFourWithoutMovingTheSurface) {
  const TriangleMesh sphere = synth::icosphere(2);
  const std::size_t edges = sphere.faces.size() * 3 / 2;
  const std::vector<float> limit(sphere.vertices.size(), 0.5f * static_cast<float>(mean_edge_length(sphere)));
  const EdgeSplitResult result = split_long_edges(sphere, limit, 1000000);
  EXPECT_EQ(result.split_edges, static_cast<int>(edges));
  EXPECT_FALSE(result.budget_reached);
  EXPECT_EQ(result.mesh.faces.size(), 4 * sphere.faces.size());
  EXPECT_EQ(result.mesh.vertices.size(), sphere.vertices.size() + edges);
  expect_closed_manifold(result.mesh);
  // Midpoints of flat faces: the enclosed volume is the input's.
  EXPECT_NEAR(testing::enclosed_volume(result.mesh) / testing::enclosed_volume(sphere), 1.0, 1e-5);
  // The input's vertices keep their indices and positions.
  for (std::size_t v = 0; v < sphere.vertices.size(); ++v) EXPECT_EQ(result.mesh.vertices[v], sphere.vertices[v]);
}

TEST(EdgeSplit, LocalLimitSplitsOnlyThereAndLeavesNoHangingVertex) {
  TriangleMesh sphere = synth::icosphere(3);
  sphere.normals = sphere.vertices;  // unit sphere: the position is the normal
  sphere.vertex_scalars["quality"] = std::vector<float>(sphere.vertices.size(), 2.0f);
  std::vector<float> limit(sphere.vertices.size(), kNever);
  for (std::size_t v = 0; v < sphere.vertices.size(); ++v) {
    if (sphere.vertices[v].x() > 0.5f) limit[v] = 0.1f * static_cast<float>(mean_edge_length(sphere));
  }
  const EdgeSplitResult result = split_long_edges(sphere, limit, 1000000);
  ASSERT_GT(result.split_edges, 0);
  expect_closed_manifold(result.mesh);
  result.mesh.check_consistent();
  for (std::size_t v = sphere.vertices.size(); v < result.mesh.vertices.size(); ++v) {
    // Only edges with an end in the fine region (x > 0.5) and the faces
    // closing them (red-green) are split; none far from it.
    EXPECT_GT(result.mesh.vertices[v].x(), 0.2f);
    EXPECT_NEAR(result.mesh.normals[v].norm(), 1.0f, 1e-5f);
    EXPECT_FLOAT_EQ(result.mesh.vertex_scalars.at("quality")[v], 2.0f);
  }
  EXPECT_LT(result.mesh.faces.size(), 2 * sphere.faces.size());
}

TEST(EdgeSplit, FaceBudgetSplitsTheLongestEdgesFirst) {
  TriangleMesh sphere = synth::icosphere(3);
  for (Eigen::Vector3f& p : sphere.vertices) p.x() *= 3.0f;  // long edges along x
  const std::vector<float> limit(sphere.vertices.size(), 1e-6f);
  const std::size_t budget = sphere.faces.size() + 200;  // at most 100 split edges
  const EdgeSplitResult result = split_long_edges(sphere, limit, budget);
  EXPECT_TRUE(result.budget_reached);
  expect_closed_manifold(result.mesh);
  EXPECT_GE(result.split_edges, 90);  // fewer where the red-green closure adds edges
  EXPECT_LE(result.mesh.faces.size(), budget);
  // Which input edges were split: those whose midpoint is a new vertex.
  std::set<std::array<float, 3>> midpoints;
  for (std::size_t v = sphere.vertices.size(); v < result.mesh.vertices.size(); ++v) {
    const Eigen::Vector3f& p = result.mesh.vertices[v];
    midpoints.insert({p.x(), p.y(), p.z()});
  }
  std::vector<float> lengths;
  std::vector<std::pair<float, bool>> edges;
  for (const Eigen::Vector3i& f : sphere.faces) {
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3f& a = sphere.vertices[f[c]];
      const Eigen::Vector3f& b = sphere.vertices[f[(c + 1) % 3]];
      const Eigen::Vector3f m = 0.5f * (a + b);
      edges.emplace_back((a - b).norm(), midpoints.count({m.x(), m.y(), m.z()}) > 0);
      lengths.push_back(edges.back().first);
    }
  }
  // Each edge appears twice (once per face): the 90 longest are the first 180.
  std::sort(lengths.begin(), lengths.end(), std::greater<>());
  const float threshold = lengths[179];
  for (const auto& [length, split] : edges) {
    if (length > threshold * 1.0001f) {
      EXPECT_TRUE(split) << "an edge of length " << length << " was kept";
    }
  }
}

}  // namespace
}  // namespace hos::refine
