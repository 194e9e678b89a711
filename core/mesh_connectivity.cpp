#include "core/mesh_connectivity.h"

#include <utility>

#include "core/disjoint_sets.h"

namespace hos {

MeshEdges mesh_edges(const TriangleMesh& mesh) {
  // Step 1: every side, collapsed ones apart.
  MeshEdges edges;
  edges.sides.reserve(3 * mesh.faces.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int a = mesh.faces[f][c], b = mesh.faces[f][(c + 1) % 3];
      (a == b ? edges.collapsed : edges.sides).push_back({edge_key(a, b), static_cast<int>(f), c});
    }
  }
  // Step 2: sorted by edge, then face, an edge's sides are adjacent.
  std::sort(edges.sides.begin(), edges.sides.end(),
            [](const FaceSide& x, const FaceSide& y) { return x.edge != y.edge ? x.edge < y.edge : x.face < y.face; });
  for (std::size_t i = 1; i <= edges.sides.size(); ++i) {
    if (i == edges.sides.size() || edges.sides[i].edge != edges.sides[i - 1].edge) edges.offsets.push_back(i);
  }
  return edges;
}

std::vector<std::array<int, 3>> face_neighbors(const MeshEdges& edges, std::size_t num_faces) {
  std::vector<std::array<int, 3>> neighbors(num_faces, {-1, -1, -1});
  for (std::size_t e = 0; e < edges.size(); ++e) {
    for (std::size_t k = edges.offsets[e]; k + 1 < edges.offsets[e + 1]; k += 2) {
      const FaceSide& x = edges.sides[k];
      const FaceSide& y = edges.sides[k + 1];
      if (x.face == y.face) continue;
      neighbors[x.face][x.corner] = y.face;
      neighbors[y.face][y.corner] = x.face;
    }
  }
  return neighbors;
}

std::vector<bool> vertices_off_two_sided_edges(const MeshEdges& edges, std::size_t num_vertices) {
  std::vector<bool> off(num_vertices, false);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    if (edges.side_count(e) == 2) continue;
    const std::uint64_t key = edges.first_side(e).edge;
    off[key >> 32] = true;
    off[key & 0xFFFFFFFFu] = true;
  }
  std::vector<int> collapsed(num_vertices, 0);
  for (const FaceSide& side : edges.collapsed) ++collapsed[side.edge >> 32];
  for (std::size_t v = 0; v < num_vertices; ++v) {
    if (collapsed[v] != 0 && collapsed[v] != 2) off[v] = true;
  }
  return off;
}

VertexFaces vertex_faces(const TriangleMesh& mesh) {
  const std::size_t num_vertices = mesh.vertices.size();
  VertexFaces out;
  out.offsets.assign(num_vertices + 1, 0);
  for (const Eigen::Vector3i& face : mesh.faces) {
    for (int c = 0; c < 3; ++c) ++out.offsets[face[c] + 1];
  }
  for (std::size_t v = 0; v < num_vertices; ++v) out.offsets[v + 1] += out.offsets[v];
  out.faces.resize(out.offsets.back());
  std::vector<int> cursor(out.offsets.begin(), out.offsets.end() - 1);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (int c = 0; c < 3; ++c) out.faces[cursor[mesh.faces[f][c]]++] = static_cast<int>(f);
  }
  return out;
}

VertexRings vertex_rings(const TriangleMesh& mesh) {
  // Step 1: every side of every face, both ways.
  std::vector<std::pair<int, int>> sides;
  sides.reserve(mesh.faces.size() * 6);
  for (const Eigen::Vector3i& f : mesh.faces) {
    for (int c = 0; c < 3; ++c) {
      sides.emplace_back(f[c], f[(c + 1) % 3]);
      sides.emplace_back(f[(c + 1) % 3], f[c]);
    }
  }
  // Step 2: sorted and unique, they are the CSR rows.
  std::sort(sides.begin(), sides.end());
  sides.erase(std::unique(sides.begin(), sides.end()), sides.end());
  VertexRings rings;
  rings.offsets.assign(mesh.vertices.size() + 1, 0);
  rings.neighbors.reserve(sides.size());
  for (const auto& [a, b] : sides) {
    ++rings.offsets[a + 1];
    rings.neighbors.push_back(b);
  }
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) rings.offsets[v + 1] += rings.offsets[v];
  return rings;
}

MeshPieces connected_pieces(const TriangleMesh& mesh) {
  DisjointSets sets(mesh.vertices.size());
  for (const Eigen::Vector3i& f : mesh.faces) {
    sets.unite(f[1], f[0]);
    sets.unite(f[2], f[0]);
  }
  MeshPieces pieces;
  std::vector<int> piece_of_root(mesh.vertices.size(), -1);
  pieces.face_piece.resize(mesh.faces.size());
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
    int& p = piece_of_root[sets.find(mesh.faces[i][0])];
    if (p < 0) p = pieces.count++;
    pieces.face_piece[i] = p;
  }
  return pieces;
}

}  // namespace hos
