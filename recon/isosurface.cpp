#include "recon/isosurface.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <unordered_map>

namespace hos::recon {
namespace {

// Cube corners by bit (x = bit 0, y = bit 1, z = bit 2); the six tetrahedra
// share the diagonal 0-7 and follow one axis order each.
constexpr std::array<std::array<int, 4>, 6> kTetrahedra = {{
    {0, 1, 3, 7},
    {0, 1, 5, 7},
    {0, 2, 3, 7},
    {0, 2, 6, 7},
    {0, 4, 5, 7},
    {0, 4, 6, 7},
}};

Eigen::Vector3i corner_offset(int c) { return {c & 1, (c >> 1) & 1, (c >> 2) & 1}; }

class SurfaceBuilder {
 public:
  SurfaceBuilder(const ScalarGrid& f, double iso) : f_(f), iso_(iso) {
    // Node keys cover the grid plus the ghost ring.
    ext_ = f.geometry.dims + Eigen::Vector3i::Constant(2);
  }

  void add_tetrahedron(const std::array<Eigen::Vector3i, 4>& nodes,
                       const std::array<double, 4>& values) {
    int inside[4], outside[4];
    int ni = 0, no = 0;
    for (int v = 0; v < 4; ++v) {
      if (values[v] < iso_) {
        inside[ni++] = v;
      } else {
        outside[no++] = v;
      }
    }
    if (ni == 0 || no == 0) return;
    Eigen::Vector3d in_centre = Eigen::Vector3d::Zero(), out_centre = Eigen::Vector3d::Zero();
    for (int v = 0; v < ni; ++v) in_centre += nodes[inside[v]].cast<double>() / ni;
    for (int v = 0; v < no; ++v) out_centre += nodes[outside[v]].cast<double>() / no;
    const Eigen::Vector3d outward = out_centre - in_centre;
    // Each cut vertex with the midpoint of its edge: orientation is decided on
    // the midpoints, which never degenerate even when the interpolated
    // vertices coincide (f exactly at the isovalue on a node).
    struct Cut {
      int vertex;
      Eigen::Vector3d midpoint;
    };
    const auto cut = [&](int a, int b) {
      return Cut{edge_vertex(nodes[a], values[a], nodes[b], values[b]),
                 0.5 * (nodes[a] + nodes[b]).cast<double>()};
    };
    if (ni == 1) {
      add_triangle(cut(inside[0], outside[0]), cut(inside[0], outside[1]), cut(inside[0], outside[2]),
                   outward);
    } else if (no == 1) {
      add_triangle(cut(inside[0], outside[0]), cut(inside[1], outside[0]), cut(inside[2], outside[0]),
                   outward);
    } else {
      // Two inside (a, b), two outside (c, d): the cut is the quad a-c, a-d, b-d, b-c.
      const Cut q0 = cut(inside[0], outside[0]), q1 = cut(inside[0], outside[1]),
                q2 = cut(inside[1], outside[1]), q3 = cut(inside[1], outside[0]);
      add_triangle(q0, q1, q2, outward);
      add_triangle(q0, q2, q3, outward);
    }
  }

  TriangleMesh take() { return std::move(mesh_); }

 private:
  int edge_vertex(const Eigen::Vector3i& a, double fa, const Eigen::Vector3i& b, double fb) {
    // Key: the lower end node and the Freudenthal direction (1..7) to the other.
    const bool a_low = (b - a).minCoeff() >= 0;
    const Eigen::Vector3i low = a_low ? a : b;
    const Eigen::Vector3i dir = a_low ? Eigen::Vector3i(b - a) : Eigen::Vector3i(a - b);
    const std::int64_t node =
        (std::int64_t{low.z() + 1} * ext_.y() + (low.y() + 1)) * ext_.x() + (low.x() + 1);
    const std::int64_t key = node * 8 + (dir.x() | (dir.y() << 1) | (dir.z() << 2));
    const auto [it, inserted] = vertices_.try_emplace(key, static_cast<int>(mesh_.vertices.size()));
    if (inserted) {
      // Kept off the end nodes so that cuts of different edges never coincide
      // (f exactly at the isovalue on a node would give zero-area faces).
      const double t = std::clamp((iso_ - fa) / (fb - fa), 1e-4, 1.0 - 1e-4);
      const Eigen::Vector3d pa = f_.geometry.position(a.x(), a.y(), a.z());
      const Eigen::Vector3d pb = f_.geometry.position(b.x(), b.y(), b.z());
      mesh_.vertices.push_back((pa + t * (pb - pa)).cast<float>());
    }
    return it->second;
  }

  template <typename Cut>
  void add_triangle(const Cut& a, const Cut& b, const Cut& c, const Eigen::Vector3d& outward) {
    if (a.vertex == b.vertex || b.vertex == c.vertex || a.vertex == c.vertex) return;
    const Eigen::Vector3d n = (b.midpoint - a.midpoint).cross(c.midpoint - a.midpoint);
    if (n.dot(outward) < 0.0) {
      mesh_.faces.emplace_back(a.vertex, c.vertex, b.vertex);
    } else {
      mesh_.faces.emplace_back(a.vertex, b.vertex, c.vertex);
    }
  }

  const ScalarGrid& f_;
  double iso_;
  Eigen::Vector3i ext_;
  std::unordered_map<std::int64_t, int> vertices_;
  TriangleMesh mesh_;
};

}  // namespace

TriangleMesh extract_isosurface(const ScalarGrid& f, double isovalue) {
  SurfaceBuilder builder(f, isovalue);
  const Eigen::Vector3i d = f.geometry.dims;
  for (int k = -1; k < d.z(); ++k) {
    for (int j = -1; j < d.y(); ++j) {
      for (int i = -1; i < d.x(); ++i) {
        std::array<double, 8> values;
        bool any_in = false, any_out = false;
        for (int c = 0; c < 8; ++c) {
          const Eigen::Vector3i o = corner_offset(c);
          values[c] = f.at(i + o.x(), j + o.y(), k + o.z());
          (values[c] < isovalue ? any_in : any_out) = true;
        }
        if (!any_in || !any_out) continue;
        const Eigen::Vector3i base(i, j, k);
        for (const auto& tet : kTetrahedra) {
          std::array<Eigen::Vector3i, 4> nodes;
          std::array<double, 4> vals;
          for (int v = 0; v < 4; ++v) {
            nodes[v] = base + corner_offset(tet[v]);
            vals[v] = values[tet[v]];
          }
          builder.add_tetrahedron(nodes, vals);
        }
      }
    }
  }
  TriangleMesh mesh = builder.take();
  compute_vertex_normals(mesh);
  return mesh;
}

void compute_vertex_normals(TriangleMesh& mesh) {
  mesh.normals.assign(mesh.vertices.size(), Eigen::Vector3f::Zero());
  for (const auto& face : mesh.faces) {
    const Eigen::Vector3f n = (mesh.vertices[face[1]] - mesh.vertices[face[0]])
                                  .cross(mesh.vertices[face[2]] - mesh.vertices[face[0]]);
    for (int c = 0; c < 3; ++c) mesh.normals[face[c]] += n;
  }
  for (auto& n : mesh.normals) {
    const float len = n.norm();
    if (len > 0.0f) n /= len;
  }
}

}  // namespace hos::recon
