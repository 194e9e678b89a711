#include "tests/eval/test_meshes.h"

#include <Eigen/Geometry>
#include <map>

namespace hos::eval::testing {

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

}  // namespace hos::eval::testing
