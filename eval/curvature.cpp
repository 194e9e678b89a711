#include "eval/curvature.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/mesh_connectivity.h"
#include "core/statistics.h"
#include "eval/surface_distance.h"

namespace hos::eval {
namespace {

double cotangent(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  const double s = u.cross(v).norm();
  return s > 0.0 ? u.dot(v) / s : 0.0;
}

}  // namespace

VertexCurvature compute_vertex_curvature(const TriangleMesh& mesh) {
  const std::size_t nv = mesh.vertices.size();
  std::vector<Eigen::Vector3d> laplacian(nv, Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> normal(nv, Eigen::Vector3d::Zero());
  std::vector<double> angle_sum(nv, 0.0);
  VertexCurvature out;
  out.mixed_area.assign(nv, 0.0);
  std::vector<bool> referenced(nv, false);
  for (const Eigen::Vector3i& f : mesh.faces) {
    const Eigen::Vector3d x[3] = {mesh.vertices[f[0]].cast<double>(), mesh.vertices[f[1]].cast<double>(),
                                  mesh.vertices[f[2]].cast<double>()};
    const Eigen::Vector3d n = (x[1] - x[0]).cross(x[2] - x[0]);
    const double area = 0.5 * n.norm();
    for (int c = 0; c < 3; ++c) referenced[f[c]] = true;
    if (!(area > 0.0)) continue;
    double angle[3], cot[3];
    bool obtuse = false;
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d u = x[(c + 1) % 3] - x[c], v = x[(c + 2) % 3] - x[c];
      angle[c] = std::atan2(u.cross(v).norm(), u.dot(v));
      cot[c] = cotangent(u, v);
      obtuse = obtuse || angle[c] > M_PI / 2;
    }
    for (int c = 0; c < 3; ++c) {
      const int i = f[c], j = f[(c + 1) % 3], k = f[(c + 2) % 3];
      const Eigen::Vector3d& xi = x[c];
      const Eigen::Vector3d& xj = x[(c + 1) % 3];
      const Eigen::Vector3d& xk = x[(c + 2) % 3];
      // Edge (j, k) is opposite corner c.
      laplacian[j] += cot[c] * (xj - xk);
      laplacian[k] += cot[c] * (xk - xj);
      angle_sum[i] += angle[c];
      normal[i] += n;  // area-weighted
      double a;
      if (!obtuse) {
        // Voronoi region of corner c (Meyer Eq. 7): edges from c to j and k,
        // each weighted by the cotangent of the angle opposite it.
        a = ((xj - xi).squaredNorm() * cot[(c + 2) % 3] + (xk - xi).squaredNorm() * cot[(c + 1) % 3]) / 8.0;
      } else {
        a = angle[c] > M_PI / 2 ? area / 2.0 : area / 4.0;
      }
      out.mixed_area[i] += a;
    }
  }
  const std::vector<bool> boundary = vertices_off_two_sided_edges(mesh_edges(mesh), nv);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.mean.assign(nv, nan);
  out.gaussian.assign(nv, nan);
  out.defined.assign(nv, false);
  for (std::size_t i = 0; i < nv; ++i) {
    const double a = out.mixed_area[i];
    if (!referenced[i] || boundary[i] || !(a > 0.0)) continue;
    const double h = laplacian[i].norm() / (4.0 * a);
    out.mean[i] = laplacian[i].dot(normal[i]) >= 0.0 ? h : -h;
    out.gaussian[i] = (2.0 * M_PI - angle_sum[i]) / a;
    out.defined[i] = std::isfinite(out.mean[i]) && std::isfinite(out.gaussian[i]);
  }
  return out;
}

CurvatureStats compute_curvature_stats(const TriangleMesh& mesh,
                                       const std::vector<Eigen::Vector3f>* points,
                                       Reporter& reporter) {
  CurvatureStats s;
  s.triangles = mesh.faces.size();
  const VertexCurvature vc = compute_vertex_curvature(mesh);
  double sum_h = 0.0, sum_k = 0.0;
  std::vector<double> abs_h, abs_k;
  for (std::size_t i = 0; i < vc.defined.size(); ++i) {
    if (!vc.defined[i]) continue;
    ++s.vertices_measured;
    const double h = std::abs(vc.mean[i]), k = std::abs(vc.gaussian[i]);
    sum_h += h;
    sum_k += k;
    s.max_abs_h = std::max(s.max_abs_h, h);
    s.max_abs_k = std::max(s.max_abs_k, k);
    abs_h.push_back(h);
    abs_k.push_back(k);
  }
  if (s.vertices_measured > 0) {
    s.mean_abs_h = sum_h / static_cast<double>(s.vertices_measured);
    s.mean_abs_k = sum_k / static_cast<double>(s.vertices_measured);
    s.p99_abs_h = quantile(std::move(abs_h), 0.99);
    s.p99_abs_k = quantile(std::move(abs_k), 0.99);
  }
  if (points != nullptr && !points->empty()) {
    reporter.begin("point distances", static_cast<std::int64_t>(points->size()));
    const DistanceStats d = summarize_distances(distances_to_mesh(*points, mesh, reporter));
    reporter.end();
    s.rms_point_distance = d.rms;
  }
  return s;
}

}  // namespace hos::eval
