// Exact nearest-point queries against a triangle mesh through an AABB tree
// (bounding-volume hierarchy, median split on the longest axis).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/types.h"

namespace hos::eval {

// Closest point of triangle (a, b, c) to p (Ericson, Real-Time Collision
// Detection, Sec. 5.1.5): Voronoi regions of vertices, edges, then the face.
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p,
                                          const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c);

struct NearestSurfacePoint {
  double distance = 0.0;
  int face = -1;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};

class TriangleTree {
 public:
  // Keeps its own copy of the triangles. Throws NumericalError for a mesh
  // without faces.
  explicit TriangleTree(const TriangleMesh& mesh);

  // Exact nearest point on the mesh (thread-safe).
  NearestSurfacePoint nearest(const Eigen::Vector3d& p) const;
  std::size_t num_triangles() const { return triangles_.size(); }

 private:
  struct Node {
    Eigen::Vector3f lo, hi;
    std::int32_t first = 0;  // leaf: first triangle index in order_; inner: left child
    std::int32_t count = 0;  // leaf: number of triangles; inner: 0 (right child = left + 1)
  };
  struct Triangle {
    Eigen::Vector3d a, b, c;
  };
  int build(int begin, int end, std::vector<Eigen::Vector3f>& centroids);

  std::vector<Triangle> triangles_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

}  // namespace hos::eval
