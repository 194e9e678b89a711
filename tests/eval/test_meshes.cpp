#include "tests/eval/test_meshes.h"

#include <Eigen/Geometry>
#include <map>

namespace hos::testing {

TriangleMesh icosphere(int levels, double radius, const Eigen::Vector3f& centre) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<Eigen::Vector3i> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                                    {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      if (auto it = midpoint.find(key); it != midpoint.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return midpoint[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<Eigen::Vector3i> next;
    for (const auto& tri : f) {
      const int ab = mid(tri[0], tri[1]), bc = mid(tri[1], tri[2]), ca = mid(tri[2], tri[0]);
      next.push_back({tri[0], ab, ca});
      next.push_back({tri[1], bc, ab});
      next.push_back({tri[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    f = std::move(next);
  }
  TriangleMesh mesh;
  for (const auto& p : v) mesh.vertices.push_back((radius * p).cast<float>() + centre);
  mesh.faces = f;
  return mesh;
}

TriangleMesh cube(float size, const Eigen::Vector3f& offset, int n) {
  TriangleMesh mesh;
  std::map<std::array<int, 3>, int> index;  // integer grid coordinates -> vertex
  auto vertex = [&](const Eigen::Vector3i& g) {
    const std::array<int, 3> key{g[0], g[1], g[2]};
    if (auto it = index.find(key); it != index.end()) return it->second;
    mesh.vertices.push_back(offset + g.cast<float>() * (size / static_cast<float>(n)));
    return index[key] = static_cast<int>(mesh.vertices.size()) - 1;
  };
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          auto g = [&](int di, int dj) {
            Eigen::Vector3i p;
            p[axis] = side * n;
            p[u] = i + di;
            p[w] = j + dj;
            return vertex(p);
          };
          const int a = g(0, 0), b = g(1, 0), c = g(1, 1), d = g(0, 1);
          // (u, w, axis) is right-handed, so a->b->c is counter-clockwise seen from +axis.
          if (side == 1) {
            mesh.faces.push_back({a, b, c});
            mesh.faces.push_back({a, c, d});
          } else {
            mesh.faces.push_back({a, c, b});
            mesh.faces.push_back({a, d, c});
          }
        }
      }
    }
  }
  return mesh;
}

}  // namespace hos::testing
