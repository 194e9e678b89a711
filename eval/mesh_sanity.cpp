#include "eval/mesh_sanity.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/disjoint_sets.h"
#include "core/mesh_connectivity.h"

namespace hos::eval {

MeshSanity check_mesh_sanity(const TriangleMesh& mesh, double relative_area_epsilon) {
  MeshSanity s;
  const std::size_t nv = mesh.vertices.size();
  const std::size_t nf = mesh.faces.size();
  s.faces = nf;
  const double diag = bounding_box(mesh.vertices).diagonal();
  const double min_area = relative_area_epsilon * diag * diag;

  std::vector<bool> referenced(nv, false);
  for (std::size_t f = 0; f < nf; ++f) {
    const Eigen::Vector3i& t = mesh.faces[f];
    const bool repeated = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
    const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>();
    const double area =
        0.5 * (mesh.vertices[t[1]].cast<double>() - a).cross(mesh.vertices[t[2]].cast<double>() - a).norm();
    if (repeated || !(area > min_area)) ++s.degenerate_faces;
    for (int c = 0; c < 3; ++c) referenced[t[c]] = true;
  }

  // Corners (face, corner) around a vertex are joined across manifold edges;
  // a vertex whose corners form more than one group is not vertex-manifold.
  const MeshEdges edges = mesh_edges(mesh);
  DisjointSets corners(3 * nf);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const std::size_t count = edges.side_count(e);
    ++s.edges;
    if (count == 1) ++s.boundary_edges;
    if (count > 2) ++s.non_manifold_edges;
    if (count == 2) {
      const FaceSide& a = edges.sides[edges.offsets[e]];
      const FaceSide& b = edges.sides[edges.offsets[e] + 1];
      if (a.forward(mesh) == b.forward(mesh)) ++s.inconsistent_edges;
      for (int ka = 0; ka < 2; ++ka) {
        const int kb = (ka == 0 ? a.from(mesh) : a.to(mesh)) == b.from(mesh) ? 0 : 1;
        corners.unite(3 * a.face + (a.corner + ka) % 3, 3 * b.face + (b.corner + kb) % 3);
      }
    }
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
  s.vertices = static_cast<std::size_t>(std::count(referenced.begin(), referenced.end(), true));
  s.unreferenced_vertices = nv - s.vertices;
  s.components = static_cast<std::size_t>(connected_pieces(mesh).count);
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
