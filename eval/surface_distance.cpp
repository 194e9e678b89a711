#include "eval/surface_distance.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <nanoflann.hpp>
#include <random>

#include "core/error.h"
#include "eval/triangle_tree.h"

namespace hos::eval {
namespace {

struct PointAdaptor {
  const std::vector<Eigen::Vector3f>& pts;
  std::size_t kdtree_get_point_count() const { return pts.size(); }
  float kdtree_get_pt(std::size_t i, std::size_t dim) const { return pts[i][static_cast<int>(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using PointKdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, PointAdaptor>, PointAdaptor, 3>;

std::vector<double> distances_to_points(const std::vector<Eigen::Vector3f>& queries,
                                        const std::vector<Eigen::Vector3f>& points,
                                        Reporter& reporter) {
  PointAdaptor adaptor{points};
  PointKdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  std::vector<double> out(queries.size());
  const std::int64_t n = static_cast<std::int64_t>(queries.size());
#pragma omp parallel for schedule(dynamic, 4096)
  for (std::int64_t i = 0; i < n; ++i) {
    unsigned int index = 0;
    float d2 = 0.0f;
    tree.knnSearch(queries[i].data(), 1, &index, &d2);
    // Recompute in double: the tree's float squared distance loses digits.
    out[i] = (queries[i].cast<double>() - points[index].cast<double>()).norm();
  }
  reporter.throw_if_cancelled();
  return out;
}

}  // namespace

void SurfaceDistanceOptions::validate() const {
  if (num_samples < 1000) throw ConfigError("eval.num_samples", "must be >= 1000");
  if (thresholds.empty()) throw ConfigError("eval.thresholds", "at least one threshold is needed");
  for (double t : thresholds) {
    if (!(t > 0.0) || !std::isfinite(t)) {
      throw ConfigError("eval.thresholds", std::to_string(t) + ": every threshold must be > 0");
    }
  }
}

std::vector<Eigen::Vector3f> sample_surface_uniform(const TriangleMesh& mesh, std::size_t n, std::uint64_t seed) {
  std::vector<double> cumulative(mesh.faces.size());
  double total = 0.0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Eigen::Vector3i& idx = mesh.faces[f];
    const Eigen::Vector3d a = mesh.vertices[idx[0]].cast<double>();
    const double area =
        0.5 * (mesh.vertices[idx[1]].cast<double>() - a).cross(mesh.vertices[idx[2]].cast<double>() - a).norm();
    total += std::isfinite(area) ? area : 0.0;
    cumulative[f] = total;
  }
  if (!(total > 0.0)) throw NumericalError("eval", "cannot sample a surface of zero area");
  // std::mt19937_64 is specified bit-exactly; the distributions are not, so
  // the uniform variates are derived from its raw output here.
  std::mt19937_64 rng(seed);
  auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  std::vector<Eigen::Vector3f> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double target = uniform() * total;
    std::size_t f =
        static_cast<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), target) - cumulative.begin());
    f = std::min(f, cumulative.size() - 1);
    double r1 = uniform(), r2 = uniform();
    if (r1 + r2 > 1.0) {  // reflect into the triangle: uniform barycentrics
      r1 = 1.0 - r1;
      r2 = 1.0 - r2;
    }
    const Eigen::Vector3i& idx = mesh.faces[f];
    const Eigen::Vector3d a = mesh.vertices[idx[0]].cast<double>();
    const Eigen::Vector3d b = mesh.vertices[idx[1]].cast<double>();
    const Eigen::Vector3d c = mesh.vertices[idx[2]].cast<double>();
    out[i] = (a + r1 * (b - a) + r2 * (c - a)).cast<float>();
  }
  return out;
}

DistanceStats summarize_distances(std::vector<double> d) {
  DistanceStats s;
  s.count = d.size();
  if (d.empty()) return s;
  double sum = 0.0, sum_sq = 0.0;
  for (double x : d) {
    if (!std::isfinite(x)) throw NumericalError("eval", "a non-finite distance was measured");
    sum += x;
    sum_sq += x * x;
  }
  const double n = static_cast<double>(d.size());
  s.mean = sum / n;
  s.rms = std::sqrt(sum_sq / n);
  std::sort(d.begin(), d.end());
  // Nearest-rank percentiles on the sorted samples.
  auto percentile = [&d](double q) {
    const std::size_t k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(d.size())));
    return d[std::min(d.size() - 1, k == 0 ? 0 : k - 1)];
  };
  s.median = percentile(0.5);
  s.p90 = percentile(0.9);
  s.max = d.back();
  return s;
}

std::vector<double> distances_to_mesh(const std::vector<Eigen::Vector3f>& points,
                                      const TriangleMesh& mesh,
                                      Reporter& reporter) {
  const TriangleTree tree(mesh);
  std::vector<double> out(points.size());
  const std::int64_t n = static_cast<std::int64_t>(points.size());
  const std::int64_t chunk = 65536;
  for (std::int64_t begin = 0; begin < n; begin += chunk) {
    const std::int64_t end = std::min(n, begin + chunk);
#pragma omp parallel for schedule(dynamic, 1024)
    for (std::int64_t i = begin; i < end; ++i) out[i] = tree.nearest(points[i].cast<double>()).distance;
    reporter.advance(end - begin);
    reporter.throw_if_cancelled();
  }
  return out;
}

SurfaceComparison compare_surfaces(const TriangleMesh& result,
                                   const TriangleMesh& truth,
                                   const SurfaceDistanceOptions& options,
                                   Reporter& reporter) {
  options.validate();
  if (truth.faces.empty()) throw NumericalError("eval", "the truth must be a mesh with faces");
  if (result.vertices.empty()) throw NumericalError("eval", "the result has no vertices");
  SurfaceComparison out;
  out.truth_diagonal = bounding_box(truth.vertices).diagonal();
  out.result_is_points = result.faces.empty();

  const std::vector<Eigen::Vector3f> truth_samples = sample_surface_uniform(truth, options.num_samples, options.seed);
  const std::vector<Eigen::Vector3f> result_samples =
      out.result_is_points ? result.vertices : sample_surface_uniform(result, options.num_samples, options.seed + 1);

  reporter.begin("accuracy", static_cast<std::int64_t>(result_samples.size()));
  std::vector<double> acc = distances_to_mesh(result_samples, truth, reporter);
  reporter.end();
  reporter.begin("completeness", static_cast<std::int64_t>(truth_samples.size()));
  std::vector<double> comp = out.result_is_points ? distances_to_points(truth_samples, result.vertices, reporter)
                                                  : distances_to_mesh(truth_samples, result, reporter);
  reporter.end();

  for (double fraction : options.thresholds) {
    ThresholdScore s;
    s.fraction = fraction;
    s.distance = fraction * out.truth_diagonal;
    const auto within = [&s](const std::vector<double>& d) {
      return static_cast<double>(std::count_if(d.begin(), d.end(), [&s](double x) { return x <= s.distance; })) /
             static_cast<double>(d.size());
    };
    s.precision = within(acc);
    s.recall = within(comp);
    s.f_score = s.precision + s.recall > 0.0 ? 2.0 * s.precision * s.recall / (s.precision + s.recall) : 0.0;
    out.scores.push_back(s);
  }
  out.accuracy = summarize_distances(std::move(acc));
  out.completeness = summarize_distances(std::move(comp));
  out.chamfer = 0.5 * (out.accuracy.mean + out.completeness.mean);
  return out;
}

ZoneDistances distances_by_zone(const TriangleMesh& from,
                                const TriangleMesh& to,
                                std::size_t n,
                                std::uint64_t seed,
                                const std::function<bool(const Eigen::Vector3f&)>& in_zone,
                                Reporter& reporter) {
  const std::vector<Eigen::Vector3f> samples = sample_surface_uniform(from, n, seed);
  const std::vector<double> d = distances_to_mesh(samples, to, reporter);
  std::vector<double> zone, rest;
  for (std::size_t i = 0; i < samples.size(); ++i) (in_zone(samples[i]) ? zone : rest).push_back(d[i]);
  return {summarize_distances(std::move(zone)), summarize_distances(std::move(rest))};
}

}  // namespace hos::eval
