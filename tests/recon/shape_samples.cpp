#include "tests/recon/shape_samples.h"

#include <Eigen/Geometry>
#include <cmath>

#include "core/mesh_connectivity.h"

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
  const MeshEdges edges = mesh_edges(mesh);
  t.edges = edges.size();
  for (std::size_t e = 0; e < edges.size(); ++e) {
    if (edges.boundary(e)) ++t.boundary_edges;
    if (edges.non_manifold(e)) ++t.nonmanifold_edges;
    if (edges.side_count(e) == 2 &&
        edges.sides[edges.offsets[e]].forward(mesh) == edges.sides[edges.offsets[e] + 1].forward(mesh)) {
      ++t.misoriented_edges;
    }
  }
  t.components = connected_pieces(mesh).count;
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
