#include "eval/triangle_tree.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace hos::eval {
namespace {

constexpr int kLeafSize = 4;

double box_squared_distance(const Eigen::Vector3d& p, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  double d = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double e = std::max({static_cast<double>(lo[k]) - p[k], 0.0, p[k] - static_cast<double>(hi[k])});
    d += e * e;
  }
  return d;
}

}  // namespace

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p,
                                          const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0.0)) {
    // Degenerate (zero-area) triangle: the nearest of its three edges.
    Eigen::Vector3d best = a;
    double best_d = (p - a).squaredNorm();
    const Eigen::Vector3d ends[3][2] = {{a, b}, {b, c}, {c, a}};
    for (const auto& e : ends) {
      const Eigen::Vector3d d = e[1] - e[0];
      const double len2 = d.squaredNorm();
      const double t = len2 > 0.0 ? std::clamp((p - e[0]).dot(d) / len2, 0.0, 1.0) : 0.0;
      const Eigen::Vector3d q = e[0] + t * d;
      if ((p - q).squaredNorm() < best_d) {
        best_d = (p - q).squaredNorm();
        best = q;
      }
    }
    return best;
  }
  const double v = vb / denom, w = vc / denom;
  return a + v * ab + w * ac;
}

TriangleTree::TriangleTree(const TriangleMesh& mesh) {
  if (mesh.faces.empty()) throw NumericalError("eval", "nearest-surface queries need a mesh with faces");
  const int n = static_cast<int>(mesh.faces.size());
  triangles_.resize(n);
  std::vector<Eigen::Vector3f> centroids(n);
  for (int f = 0; f < n; ++f) {
    const Eigen::Vector3i& idx = mesh.faces[f];
    triangles_[f] = {mesh.vertices[idx[0]].cast<double>(), mesh.vertices[idx[1]].cast<double>(),
                     mesh.vertices[idx[2]].cast<double>()};
    centroids[f] = ((triangles_[f].a + triangles_[f].b + triangles_[f].c) / 3.0).cast<float>();
  }
  order_.resize(n);
  for (int f = 0; f < n; ++f) order_[f] = f;
  nodes_.reserve(2 * (n / kLeafSize + 1));
  nodes_.emplace_back();
  build(0, n, centroids);
}

// Fills node 0 or the node the caller reserved; returns nothing useful but the
// recursion keeps children adjacent (right = left + 1).
int TriangleTree::build(int begin, int end, std::vector<Eigen::Vector3f>& centroids) {
  // Iterative to avoid deep recursion on degenerate inputs: (node, begin, end).
  struct Task {
    int node, begin, end;
  };
  std::vector<Task> stack{{0, begin, end}};
  while (!stack.empty()) {
    const Task task = stack.back();
    stack.pop_back();
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
    Eigen::Vector3f hi = Eigen::Vector3f::Constant(std::numeric_limits<float>::lowest());
    Eigen::Vector3f clo = lo, chi = hi;
    for (int i = task.begin; i < task.end; ++i) {
      const Triangle& t = triangles_[order_[i]];
      for (const Eigen::Vector3d* v : {&t.a, &t.b, &t.c}) {
        // Round outwards so float boxes never cut the double triangles.
        const Eigen::Vector3f vf = v->cast<float>();
        lo = lo.cwiseMin(vf - vf.cwiseAbs() * 1e-6f - Eigen::Vector3f::Constant(1e-30f));
        hi = hi.cwiseMax(vf + vf.cwiseAbs() * 1e-6f + Eigen::Vector3f::Constant(1e-30f));
      }
      clo = clo.cwiseMin(centroids[order_[i]]);
      chi = chi.cwiseMax(centroids[order_[i]]);
    }
    Node& node = nodes_[task.node];
    node.lo = lo;
    node.hi = hi;
    const int count = task.end - task.begin;
    int axis = 0;
    (chi - clo).maxCoeff(&axis);
    if (count <= kLeafSize || !(chi[axis] > clo[axis])) {
      node.first = task.begin;
      node.count = count;
      continue;
    }
    const int mid = task.begin + count / 2;
    std::nth_element(order_.begin() + task.begin, order_.begin() + mid, order_.begin() + task.end,
                     [&](int x, int y) { return centroids[x][axis] < centroids[y][axis]; });
    const int left = static_cast<int>(nodes_.size());
    nodes_[task.node].first = left;
    nodes_[task.node].count = 0;
    nodes_.emplace_back();
    nodes_.emplace_back();
    stack.push_back({left + 1, mid, task.end});
    stack.push_back({left, task.begin, mid});
  }
  return 0;
}

NearestSurfacePoint TriangleTree::nearest(const Eigen::Vector3d& p) const {
  NearestSurfacePoint best;
  double best_d2 = std::numeric_limits<double>::infinity();
  struct Entry {
    int node;
    double d2;
  };
  Entry stack[128];
  int top = 0;
  stack[top++] = {0, box_squared_distance(p, nodes_[0].lo, nodes_[0].hi)};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.d2 >= best_d2) continue;
    const Node& node = nodes_[e.node];
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const Triangle& t = triangles_[order_[i]];
        const Eigen::Vector3d q = closest_point_on_triangle(p, t.a, t.b, t.c);
        const double d2 = (p - q).squaredNorm();
        if (d2 < best_d2) {
          best_d2 = d2;
          best.face = order_[i];
          best.point = q;
        }
      }
      continue;
    }
    const int l = node.first, r = node.first + 1;
    const double dl = box_squared_distance(p, nodes_[l].lo, nodes_[l].hi);
    const double dr = box_squared_distance(p, nodes_[r].lo, nodes_[r].hi);
    // Push the farther child first so the nearer one is searched first.
    if (dl < dr) {
      if (dr < best_d2) stack[top++] = {r, dr};
      if (dl < best_d2) stack[top++] = {l, dl};
    } else {
      if (dl < best_d2) stack[top++] = {l, dl};
      if (dr < best_d2) stack[top++] = {r, dr};
    }
  }
  best.distance = std::sqrt(best_d2);
  return best;
}

}  // namespace hos::eval
