// Connectivity of a triangle mesh: its edges and the face sides along them,
// the faces across each face's sides, the faces and vertices around each
// vertex, and the connected pieces.
//
// A face side runs from the face's corner c to corner c + 1. A side whose two
// corners are one vertex (a face repeating an index) is no edge: MeshEdges
// lists it apart, and each function says how it counts it.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/types.h"

namespace hos {

// The undirected edge between vertices a and b as one number (smaller index
// in the high half), so that sorting by it groups an edge's sides.
inline std::uint64_t edge_key(int a, int b) {
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
}

struct FaceSide {
  std::uint64_t edge;  // edge_key of its two corners
  int face;
  int corner;  // the side runs from this corner to the next

  int from(const TriangleMesh& mesh) const { return mesh.faces[face][corner]; }
  int to(const TriangleMesh& mesh) const { return mesh.faces[face][(corner + 1) % 3]; }
  // Whether the side runs from the edge's smaller vertex index to its larger.
  bool forward(const TriangleMesh& mesh) const { return from(mesh) < to(mesh); }
};

struct MeshEdges {
  // The sides with two distinct corners, grouped by edge: edges in key order,
  // an edge's sides in face order.
  std::vector<FaceSide> sides;
  // Edge e's sides are sides[offsets[e] .. offsets[e + 1]).
  std::vector<std::size_t> offsets{0};
  // The sides whose two corners are one vertex, in face order.
  std::vector<FaceSide> collapsed;

  std::size_t size() const { return offsets.size() - 1; }
  std::size_t side_count(std::size_t e) const { return offsets[e + 1] - offsets[e]; }
  const FaceSide& first_side(std::size_t e) const { return sides[offsets[e]]; }
  bool boundary(std::size_t e) const { return side_count(e) == 1; }
  bool non_manifold(std::size_t e) const { return side_count(e) > 2; }
};

MeshEdges mesh_edges(const TriangleMesh& mesh);

// The face across each side of each face (side c: corners c and c + 1), -1
// where no face is: on a boundary, and for a collapsed side. A non-manifold
// edge links its sides pairwise in face order (a face with two sides on one
// edge is not its own neighbour; that pair stays unlinked).
std::vector<std::array<int, 3>> face_neighbors(const MeshEdges& edges, std::size_t num_faces);

// Vertices on an edge that is not shared by exactly two face sides (a
// boundary or a non-manifold edge). A vertex with collapsed sides counts as
// on such an edge unless exactly two sides collapse onto it, as if the
// collapsed sides were an edge from the vertex to itself.
std::vector<bool> vertices_off_two_sided_edges(const MeshEdges& edges, std::size_t num_vertices);

// The faces around each vertex, CSR: vertex v's are faces[offsets[v] ..
// offsets[v + 1]), in face order, a face once per corner on v.
struct VertexFaces {
  std::vector<int> offsets;
  std::vector<int> faces;
};

VertexFaces vertex_faces(const TriangleMesh& mesh);

// The vertices sharing a face side with each vertex, CSR (v's are
// neighbors[offsets[v] .. offsets[v + 1]), sorted, no duplicates; v itself
// when a side collapses onto it).
struct VertexRings {
  std::vector<int> offsets;
  std::vector<int> neighbors;

  int degree(int v) const { return offsets[v + 1] - offsets[v]; }
};

VertexRings vertex_rings(const TriangleMesh& mesh);

// The connected piece of every face: faces that share a vertex are in one
// piece (a part attached at a single vertex belongs to it). Pieces are
// numbered 0 .. count - 1 in order of their first face.
struct MeshPieces {
  std::vector<int> face_piece;
  int count = 0;
};

MeshPieces connected_pieces(const TriangleMesh& mesh);

}  // namespace hos
