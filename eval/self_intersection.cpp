#include "eval/self_intersection.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace hos::eval {
namespace {

using Vec3 = Eigen::Vector3d;

// Whether the segment p -> q passes through the triangle's interior
// (Moller-Trumbore, both ends excluded).
bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  constexpr double kEps = 1e-12;
  const Vec3 d = q - p, e1 = b - a, e2 = c - a;
  const Vec3 h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < kEps * d.norm() * e1.norm() * e2.norm()) return false;  // parallel or coplanar
  const double inv = 1.0 / det;
  const Vec3 s = p - a;
  const double u = s.dot(h) * inv;
  if (u <= 0.0 || u >= 1.0) return false;
  const Vec3 r = s.cross(e1);
  const double v = d.dot(r) * inv;
  if (v <= 0.0 || u + v >= 1.0) return false;
  const double t = e2.dot(r) * inv;
  return t > 0.0 && t < 1.0;
}

bool faces_cross(const TriangleMesh& mesh, const Eigen::Vector3i& f, const Eigen::Vector3i& g) {
  const auto corner = [&](const Eigen::Vector3i& face, int k) { return mesh.vertices[face[k]].cast<double>(); };
  for (int k = 0; k < 3; ++k) {
    if (segment_crosses_triangle(corner(f, k), corner(f, (k + 1) % 3), corner(g, 0), corner(g, 1), corner(g, 2)) ||
        segment_crosses_triangle(corner(g, k), corner(g, (k + 1) % 3), corner(f, 0), corner(f, 1), corner(f, 2))) {
      return true;
    }
  }
  return false;
}

bool share_a_vertex(const Eigen::Vector3i& f, const Eigen::Vector3i& g) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (f[i] == g[j]) return true;
    }
  }
  return false;
}

}  // namespace

std::size_t count_self_intersections(const TriangleMesh& mesh) {
  const int n = static_cast<int>(mesh.faces.size());
  if (n < 2) return 0;
  // Step 1: the faces' boxes, in cells about twice the mean box size.
  std::vector<Eigen::AlignedBox3d> boxes(n);
  double extent = 0.0;
  for (int f = 0; f < n; ++f) {
    for (int k = 0; k < 3; ++k) boxes[f].extend(mesh.vertices[mesh.faces[f][k]].cast<double>());
    extent += boxes[f].diagonal().maxCoeff();
  }
  const double cell = std::max(2.0 * extent / n, 1e-12);
  const auto cell_of = [&](const Vec3& p) { return (p / cell).array().floor().cast<std::int64_t>().matrix().eval(); };
  const auto key = [](const Eigen::Matrix<std::int64_t, 3, 1>& c) {
    return static_cast<std::uint64_t>(c.x() & 0x1FFFFF) | (static_cast<std::uint64_t>(c.y() & 0x1FFFFF) << 21) |
           (static_cast<std::uint64_t>(c.z() & 0x1FFFFF) << 42);
  };
  std::unordered_map<std::uint64_t, std::vector<int>> grid;
  for (int f = 0; f < n; ++f) {
    const auto lo = cell_of(boxes[f].min()), hi = cell_of(boxes[f].max());
    for (std::int64_t z = lo.z(); z <= hi.z(); ++z) {
      for (std::int64_t y = lo.y(); y <= hi.y(); ++y) {
        for (std::int64_t x = lo.x(); x <= hi.x(); ++x) grid[key({x, y, z})].push_back(f);
      }
    }
  }
  // Step 2: the pairs of each cell whose boxes overlap, each pair tested only
  // in the first cell the two share.
  std::size_t crossings = 0;
  for (const auto& [cell_key, faces] : grid) {
    for (std::size_t i = 0; i < faces.size(); ++i) {
      for (std::size_t j = i + 1; j < faces.size(); ++j) {
        const int f = faces[i], g = faces[j];
        if (!boxes[f].intersects(boxes[g])) continue;
        if (key(cell_of(boxes[f].intersection(boxes[g]).min())) != cell_key) continue;
        if (share_a_vertex(mesh.faces[f], mesh.faces[g])) continue;
        crossings += faces_cross(mesh, mesh.faces[f], mesh.faces[g]);
      }
    }
  }
  return crossings;
}

}  // namespace hos::eval
