// The searched subset and the targets filled in between, on a flat grid
// whose distances and true offsets are known exactly.
#include "refine/search_subset.h"

#include <gtest/gtest.h>

#include <cmath>

#include "refine/mesh_geometry.h"
#include "synth/shapes.h"

namespace hos::refine {
namespace {

// side x side vertices one unit apart in the plane z = 0, two faces a cell.
TriangleMesh grid(int side) { return synth::grid_mesh(side, 1.0f); }

TEST(SearchSubset, SpacedVerticesCoverTheGridAndKeepApart) {
  const TriangleMesh mesh = grid(40);
  const VertexRings rings = vertex_rings(mesh);
  for (const float radius : {0.0f, 0.5f, 2.5f, 6.0f}) {
    const std::vector<int> searched = spaced_vertices(mesh, rings, std::vector<float>(mesh.vertices.size(), radius));
    if (radius <= 1.0f) {
      EXPECT_EQ(searched.size(), mesh.vertices.size()) << "radius " << radius << " is below every edge";
      continue;
    }
    // Every vertex within the radius of a searched one, no two searched within it.
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
      float nearest = INFINITY;
      for (int s : searched) nearest = std::min(nearest, (mesh.vertices[v] - mesh.vertices[s]).norm());
      ASSERT_LT(nearest, radius) << "vertex " << v << ", radius " << radius;
    }
    for (std::size_t i = 0; i < searched.size(); ++i) {
      for (std::size_t j = 0; j < i; ++j) {
        ASSERT_GE((mesh.vertices[searched[i]] - mesh.vertices[searched[j]]).norm(), radius);
      }
    }
    // Covering discs of the radius need at least n / (pi r^2) centres;
    // disjoint discs of half the radius fit at most 4 n / (pi r^2) (the
    // grid's border adds some).
    const double per_disc = mesh.vertices.size() / (3.14159 * radius * radius);
    EXPECT_GT(static_cast<double>(searched.size()), 0.9 * per_disc) << radius;
    EXPECT_LT(static_cast<double>(searched.size()), 1.5 * 4.0 * per_disc) << radius;
  }
}

TEST(SearchSubset, FilledTargetsFollowTheSearchedOnesAndLeaveUnreachedVerticesOut) {
  const int side = 30;
  TriangleMesh mesh = grid(side);
  // A second grid with no searched vertex: its vertices keep no target.
  const TriangleMesh other = grid(5);
  const int first_other = static_cast<int>(mesh.vertices.size());
  for (const Eigen::Vector3f& v : other.vertices) mesh.vertices.push_back(v + Eigen::Vector3f(100.0f, 0.0f, 0.0f));
  for (const Eigen::Vector3i& f : other.faces) mesh.faces.push_back(f + Eigen::Vector3i::Constant(first_other));
  const VertexRings rings = vertex_rings(mesh);
  std::vector<float> radius(mesh.vertices.size(), 3.5f);
  const std::vector<int> subset = spaced_vertices(mesh, rings, radius);
  std::vector<char> searched(mesh.vertices.size(), 0);
  std::vector<VertexTarget> targets(mesh.vertices.size());
  // The searched vertices of the first grid measure a constant offset; a
  // searched vertex of the second grid finds none (weight 0).
  for (int v : subset) {
    searched[v] = 1;
    if (v < first_other) targets[v] = {0.25f, 0.8f, 0.9f};
  }
  fill_targets(rings, searched, targets);
  for (int v = 0; v < first_other; ++v) {
    ASSERT_FLOAT_EQ(targets[v].offset, 0.25f) << v;
    ASSERT_FLOAT_EQ(targets[v].weight, 0.8f) << v;
    if (!searched[v]) {
      EXPECT_EQ(targets[v].score, 0.0f) << "a filled target was not measured";
    }
  }
  for (int v = first_other; v < static_cast<int>(mesh.vertices.size()); ++v) EXPECT_EQ(targets[v].weight, 0.0f);
}

TEST(SearchSubset, AFilledTargetIsTheWeightedMeanOfItsSearchedNeighbours) {
  // One triangle: vertex 1 lies between a confident target and a weaker one.
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  mesh.faces = {{0, 1, 2}};
  std::vector<VertexTarget> targets(3);
  targets[0] = {1.0f, 0.75f, 0.9f};
  targets[2] = {-1.0f, 0.25f, 0.9f};
  fill_targets(vertex_rings(mesh), {1, 0, 1}, targets);
  // Weight-averaged offset (0.75 - 0.25) / 1 = 0.5; mean weight 0.5.
  EXPECT_NEAR(targets[1].offset, 0.5f, 1e-6f);
  EXPECT_NEAR(targets[1].weight, 0.5f, 1e-6f);
  EXPECT_EQ(targets[0].offset, 1.0f) << "a searched target is kept";
}

}  // namespace
}  // namespace hos::refine
