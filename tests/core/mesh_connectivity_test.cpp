#include "core/mesh_connectivity.h"

#include <gtest/gtest.h>

#include <initializer_list>

namespace hos {
namespace {

// A mesh of the given faces over `vertices` points (positions do not matter
// to connectivity).
TriangleMesh mesh_of(int vertices, std::initializer_list<Eigen::Vector3i> faces) {
  TriangleMesh mesh;
  mesh.vertices.assign(vertices, Eigen::Vector3f::Zero());
  mesh.faces.assign(faces.begin(), faces.end());
  return mesh;
}

TriangleMesh tetrahedron() { return mesh_of(4, {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}}); }

std::size_t boundary_edges(const MeshEdges& edges) {
  std::size_t n = 0;
  for (std::size_t e = 0; e < edges.size(); ++e) n += edges.boundary(e);
  return n;
}

std::vector<int> ring(const VertexRings& rings, int v) {
  return {rings.neighbors.begin() + rings.offsets[v], rings.neighbors.begin() + rings.offsets[v + 1]};
}

TEST(MeshConnectivity, EdgeKeyIsSymmetricAndOrdered) {
  EXPECT_EQ(edge_key(3, 7), edge_key(7, 3));
  EXPECT_EQ(edge_key(3, 7), (std::uint64_t{3} << 32) | 7u);
  EXPECT_LT(edge_key(2, 9), edge_key(3, 4));
}

TEST(MeshConnectivity, OneTriangleIsThreeBoundaryEdges) {
  const TriangleMesh mesh = mesh_of(3, {{0, 1, 2}});
  const MeshEdges edges = mesh_edges(mesh);
  ASSERT_EQ(edges.size(), 3u);
  EXPECT_EQ(boundary_edges(edges), 3u);
  EXPECT_TRUE(edges.collapsed.empty());
  EXPECT_EQ(face_neighbors(edges, 1)[0], (std::array<int, 3>{-1, -1, -1}));
  EXPECT_EQ(vertices_off_two_sided_edges(edges, 3), std::vector<bool>(3, true));
  EXPECT_EQ(connected_pieces(mesh).count, 1);
}

TEST(MeshConnectivity, ClosedTetrahedronHasSixTwoSidedEdges) {
  const TriangleMesh mesh = tetrahedron();
  const MeshEdges edges = mesh_edges(mesh);
  ASSERT_EQ(edges.size(), 6u);  // V - E + F = 2
  for (std::size_t e = 0; e < edges.size(); ++e) {
    ASSERT_EQ(edges.side_count(e), 2u);
    const FaceSide& a = edges.sides[edges.offsets[e]];
    const FaceSide& b = edges.sides[edges.offsets[e] + 1];
    EXPECT_LT(a.face, b.face);
    EXPECT_NE(a.forward(mesh), b.forward(mesh)) << "consistently oriented faces run an edge both ways";
  }
  EXPECT_EQ(boundary_edges(edges), 0u);
  EXPECT_EQ(vertices_off_two_sided_edges(edges, 4), std::vector<bool>(4, false));
  // Face 0 = (0, 2, 1): side 0-2 is shared with face 3 (2, 0, 3), 2-1 with
  // face 2 (1, 2, 3), 1-0 with face 1 (0, 1, 3).
  const auto neighbors = face_neighbors(edges, 4);
  EXPECT_EQ(neighbors[0], (std::array<int, 3>{3, 2, 1}));
  EXPECT_EQ(neighbors[1], (std::array<int, 3>{0, 2, 3}));
  const VertexFaces around = vertex_faces(mesh);
  EXPECT_EQ(around.offsets, (std::vector<int>{0, 3, 6, 9, 12}));
  EXPECT_EQ(std::vector<int>(around.faces.begin(), around.faces.begin() + 3), (std::vector<int>{0, 1, 3}));
  const VertexRings rings = vertex_rings(mesh);
  for (int v = 0; v < 4; ++v) EXPECT_EQ(rings.degree(v), 3);
  EXPECT_EQ(ring(rings, 2), (std::vector<int>{0, 1, 3}));
}

TEST(MeshConnectivity, SquareOfTwoTrianglesHasOneInteriorEdge) {
  const TriangleMesh mesh = mesh_of(4, {{0, 1, 2}, {0, 2, 3}});
  const MeshEdges edges = mesh_edges(mesh);
  EXPECT_EQ(edges.size(), 5u);
  EXPECT_EQ(boundary_edges(edges), 4u);
  const auto neighbors = face_neighbors(edges, 2);
  EXPECT_EQ(neighbors[0], (std::array<int, 3>{-1, -1, 1}));
  EXPECT_EQ(neighbors[1], (std::array<int, 3>{0, -1, -1}));
  EXPECT_EQ(ring(vertex_rings(mesh), 0), (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(ring(vertex_rings(mesh), 1), (std::vector<int>{0, 2}));
}

TEST(MeshConnectivity, FinOfThreeFacesIsNonManifoldAndLinksTheFirstPair) {
  // Three faces on edge 0-1.
  const TriangleMesh mesh = mesh_of(5, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  const MeshEdges edges = mesh_edges(mesh);
  EXPECT_EQ(edges.size(), 7u);
  std::size_t non_manifold = 0;
  for (std::size_t e = 0; e < edges.size(); ++e) non_manifold += edges.non_manifold(e);
  EXPECT_EQ(non_manifold, 1u);
  EXPECT_EQ(edges.side_count(0), 3u) << "edge 0-1 has the smallest key";
  const auto neighbors = face_neighbors(edges, 3);
  EXPECT_EQ(neighbors[0][0], 1);
  EXPECT_EQ(neighbors[1][0], 0);
  EXPECT_EQ(neighbors[2][0], -1);
  EXPECT_EQ(vertices_off_two_sided_edges(edges, 5), std::vector<bool>(5, true));
}

TEST(MeshConnectivity, PiecesJoinAtSharedVerticesAndAreNumberedByFirstFace) {
  // Face 0 alone; faces 1 and 3 a bowtie meeting at vertex 5; face 2 alone;
  // vertex 11 unused.
  const TriangleMesh mesh = mesh_of(12, {{0, 1, 2}, {3, 4, 5}, {8, 9, 7}, {5, 6, 10}});
  const MeshPieces pieces = connected_pieces(mesh);
  EXPECT_EQ(pieces.count, 3);
  EXPECT_EQ(pieces.face_piece, (std::vector<int>{0, 1, 2, 1}));
  EXPECT_EQ(connected_pieces(mesh_of(3, {})).count, 0);
}

TEST(MeshConnectivity, CollapsedSidesAreNoEdges) {
  // Face 0 repeats vertex 0; face 1 is a plain triangle on edge 0-1.
  const TriangleMesh mesh = mesh_of(3, {{0, 0, 1}, {1, 0, 2}});
  const MeshEdges edges = mesh_edges(mesh);
  ASSERT_EQ(edges.collapsed.size(), 1u);
  EXPECT_EQ(edges.collapsed[0].face, 0);
  EXPECT_EQ(edges.collapsed[0].corner, 0);
  EXPECT_EQ(edges.size(), 3u);  // 0-1 (three sides), 0-2, 1-2
  EXPECT_EQ(edges.side_count(0), 3u);
  const auto neighbors = face_neighbors(edges, 2);
  EXPECT_EQ(neighbors[0], (std::array<int, 3>{-1, -1, -1})) << "face 0's own two sides on 0-1 are not linked";
  EXPECT_EQ(neighbors[1], (std::array<int, 3>{-1, -1, -1}));
  EXPECT_EQ(ring(vertex_rings(mesh), 0), (std::vector<int>{0, 1, 2})) << "the collapsed side makes 0 its own neighbour";
  EXPECT_EQ(vertex_faces(mesh).offsets, (std::vector<int>{0, 3, 5, 6}));
}

TEST(MeshConnectivity, TwoCollapsedSidesOnAVertexCountAsATwoSidedEdge) {
  // A face (0, 0, v) runs edge 0-v both ways (two sides), so vertex 0 is off
  // only through its collapsed sides: one is off, two are not.
  const TriangleMesh one = mesh_of(2, {{0, 0, 1}});
  EXPECT_EQ(vertices_off_two_sided_edges(mesh_edges(one), 2), (std::vector<bool>{true, false}));
  const TriangleMesh two = mesh_of(3, {{0, 0, 1}, {0, 0, 2}});
  EXPECT_EQ(vertices_off_two_sided_edges(mesh_edges(two), 3), (std::vector<bool>{false, false, false}));
}

TEST(MeshConnectivity, EmptyMeshHasNothing) {
  const TriangleMesh mesh = mesh_of(2, {});
  const MeshEdges edges = mesh_edges(mesh);
  EXPECT_EQ(edges.size(), 0u);
  EXPECT_TRUE(face_neighbors(edges, 0).empty());
  EXPECT_EQ(vertex_rings(mesh).offsets, (std::vector<int>{0, 0, 0}));
  EXPECT_EQ(vertex_faces(mesh).faces.size(), 0u);
}

}  // namespace
}  // namespace hos
