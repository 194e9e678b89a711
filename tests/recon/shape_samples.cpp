#include "tests/recon/shape_samples.h"

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

namespace hos::recon::testing {

GridGeometry cube_grid(int n, double h) {
  GridGeometry g;
  g.dims = Eigen::Vector3i::Constant(n);
  g.spacing = h;
  return g;
}

MeshTopology analyze_topology(const TriangleMesh& mesh) {
  MeshTopology t;
  t.vertices = mesh.num_vertices();
  t.faces = mesh.num_faces();
  std::map<std::pair<int, int>, std::pair<int, int>> edges;  // (min,max) -> (count, forward count)
  for (const auto& f : mesh.faces) {
    for (int c = 0; c < 3; ++c) {
      const int a = f[c], b = f[(c + 1) % 3];
      auto& e = edges[{std::min(a, b), std::max(a, b)}];
      ++e.first;
      if (a < b) ++e.second;
    }
  }
  t.edges = edges.size();
  for (const auto& [key, e] : edges) {
    if (e.first == 1) ++t.boundary_edges;
    if (e.first > 2) ++t.nonmanifold_edges;
    if (e.first == 2 && e.second != 1) ++t.misoriented_edges;
  }
  std::vector<int> parent(mesh.num_vertices());
  std::iota(parent.begin(), parent.end(), 0);
  std::function<int(int)> root = [&](int x) { return parent[x] == x ? x : parent[x] = root(parent[x]); };
  for (const auto& f : mesh.faces) {
    parent[root(f[1])] = root(f[0]);
    parent[root(f[2])] = root(f[0]);
  }
  std::set<int> roots;
  for (const auto& f : mesh.faces) roots.insert(root(f[0]));
  t.components = static_cast<int>(roots.size());
  return t;
}

double signed_volume(const TriangleMesh& mesh) {
  double v = 0.0;
  for (const auto& f : mesh.faces) {
    const Eigen::Vector3d a = mesh.vertices[f[0]].cast<double>(), b = mesh.vertices[f[1]].cast<double>(),
                          c = mesh.vertices[f[2]].cast<double>();
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

}  // namespace hos::recon::testing
