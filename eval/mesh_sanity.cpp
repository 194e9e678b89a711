#include "eval/mesh_sanity.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <numeric>
#include <vector>

namespace hos::eval {
namespace {

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(std::size_t a, std::size_t b) { parent_[find(a)] = find(b); }

 private:
  std::vector<std::size_t> parent_;
};

struct HalfEdge {
  std::uint64_t key;  // undirected (min, max)
  int face;
  int corner;    // the edge runs from corner to corner + 1
  bool forward;  // from min to max
};

}  // namespace

MeshSanity check_mesh_sanity(const TriangleMesh& mesh, double relative_area_epsilon) {
  MeshSanity s;
  const std::size_t nv = mesh.vertices.size();
  const std::size_t nf = mesh.faces.size();
  s.faces = nf;
  const double diag = bounding_box(mesh.vertices).diagonal();
  const double min_area = relative_area_epsilon * diag * diag;

  std::vector<bool> referenced(nv, false);
  std::vector<HalfEdge> half_edges;
  half_edges.reserve(3 * nf);
  UnionFind vertex_sets(nv);
  for (std::size_t f = 0; f < nf; ++f) {
    const Eigen::Vector3i& t = mesh.faces[f];
    const bool repeated = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
    const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>();
    const double area =
        0.5 * (mesh.vertices[t[1]].cast<double>() - a).cross(mesh.vertices[t[2]].cast<double>() - a).norm();
    if (repeated || !(area > min_area)) ++s.degenerate_faces;
    for (int c = 0; c < 3; ++c) {
      const int u = t[c], v = t[(c + 1) % 3];
      referenced[u] = true;
      vertex_sets.unite(u, v);
      if (u == v) continue;
      const std::uint64_t key =
          (static_cast<std::uint64_t>(std::min(u, v)) << 32) | static_cast<std::uint32_t>(std::max(u, v));
      half_edges.push_back({key, static_cast<int>(f), c, u < v});
    }
  }
  std::sort(half_edges.begin(), half_edges.end(),
            [](const HalfEdge& a, const HalfEdge& b) { return a.key != b.key ? a.key < b.key : a.face < b.face; });

  // Corners (face, corner) around a vertex are joined across manifold edges;
  // a vertex whose corners form more than one group is not vertex-manifold.
  UnionFind corners(3 * nf);
  for (std::size_t i = 0; i < half_edges.size();) {
    std::size_t j = i;
    while (j < half_edges.size() && half_edges[j].key == half_edges[i].key) ++j;
    const std::size_t count = j - i;
    ++s.edges;
    if (count == 1) ++s.boundary_edges;
    if (count > 2) ++s.non_manifold_edges;
    if (count == 2) {
      const HalfEdge& a = half_edges[i];
      const HalfEdge& b = half_edges[i + 1];
      if (a.forward == b.forward) ++s.inconsistent_edges;
      const auto vertex_at = [&mesh](const HalfEdge& h, int k) { return mesh.faces[h.face][(h.corner + k) % 3]; };
      for (int ka = 0; ka < 2; ++ka) {
        const int v = vertex_at(a, ka);
        const int kb = vertex_at(b, 0) == v ? 0 : 1;
        corners.unite(3 * a.face + (a.corner + ka) % 3, 3 * b.face + (b.corner + kb) % 3);
      }
    }
    i = j;
  }
  std::vector<std::size_t> first_group(nv, SIZE_MAX);
  std::vector<bool> non_manifold(nv, false);
  for (std::size_t f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.faces[f][c];
      const std::size_t g = corners.find(3 * f + c);
      if (first_group[v] == SIZE_MAX) {
        first_group[v] = g;
      } else if (first_group[v] != g) {
        non_manifold[v] = true;
      }
    }
  }
  s.non_manifold_vertices = static_cast<std::size_t>(std::count(non_manifold.begin(), non_manifold.end(), true));
  for (std::size_t v = 0; v < nv; ++v) {
    if (!referenced[v]) {
      ++s.unreferenced_vertices;
      continue;
    }
    ++s.vertices;
    if (vertex_sets.find(v) == v) ++s.components;
  }
  s.euler_characteristic =
      static_cast<long long>(s.vertices) - static_cast<long long>(s.edges) + static_cast<long long>(s.faces);
  s.edge_manifold = s.non_manifold_edges == 0;
  s.vertex_manifold = s.non_manifold_vertices == 0;
  s.watertight = nf > 0 && s.boundary_edges == 0 && s.edge_manifold;
  s.consistently_oriented = s.inconsistent_edges == 0;
  if (s.watertight && s.vertex_manifold && s.consistently_oriented) {
    s.genus = (2 * static_cast<long long>(s.components) - s.euler_characteristic) / 2;
  }
  return s;
}

}  // namespace hos::eval
