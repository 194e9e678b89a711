#include "recon/sample_frame.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/reporter.h"
#include "core/statistics.h"

namespace hos::recon {
namespace {

// The robust box takes the 1st and 99th percentile per axis; a point more
// than kFarFactor robust extents outside it is an outlier.
constexpr double kRobustQuantile = 0.01;
constexpr double kFarFactor = 1.0;
// Float keeps 24 bits: an extent below ~2^-16 of the coordinates' magnitude
// has too few distinct values across it to place a grid.
constexpr double kMinRelativeExtent = 1.0 / 65536.0;
// Below this the unit frame's scaling (1 / extent) would overflow float.
constexpr double kMinAbsoluteExtent = 1e-35;

// Keeps the samples within kFarFactor robust extents of the robust box;
// returns how many were dropped.
std::size_t drop_far_outliers(std::vector<Eigen::Vector3f>& points,
                              std::vector<Eigen::Vector3f>& normals,
                              std::vector<float>& weights) {
  if (points.size() < 8) return 0;
  Eigen::Vector3d lo, hi;
  std::vector<float> axis(points.size());
  for (int a = 0; a < 3; ++a) {
    for (std::size_t i = 0; i < points.size(); ++i) axis[i] = points[i][a];
    lo[a] = quantile(axis, kRobustQuantile);
    hi[a] = quantile(axis, 1.0 - kRobustQuantile);
  }
  const double reach = kFarFactor * (hi - lo).maxCoeff();
  const Eigen::Vector3d keep_lo = lo.array() - reach, keep_hi = hi.array() + reach;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d p = points[i].cast<double>();
    if ((p.array() < keep_lo.array()).any() || (p.array() > keep_hi.array()).any()) continue;
    points[kept] = points[i];
    normals[kept] = normals[i];
    if (!weights.empty()) weights[kept] = weights[i];
    ++kept;
  }
  const std::size_t dropped = points.size() - kept;
  points.resize(kept);
  normals.resize(kept);
  if (!weights.empty()) weights.resize(kept);
  return dropped;
}

}  // namespace

void check_extent(const BoundingBox& box, const std::string& source) {
  if (!box.valid()) throw InputError(source, "has no points with finite coordinates");
  const Eigen::Vector3d lo = box.min.cast<double>(), hi = box.max.cast<double>();
  const double longest = (hi - lo).maxCoeff();
  const double magnitude = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
  if (!(longest > kMinAbsoluteExtent) || !std::isfinite(longest) || longest < kMinRelativeExtent * magnitude) {
    throw InputError(source, format_message("the points' extent is ", longest, " at coordinates up to ", magnitude,
                                            ": they (nearly) coincide, so there is no surface to reconstruct "
                                            "(the extent must be above 1/65536 of the coordinates)"));
  }
}

OrientedSamples prepare_samples(const PointCloud& input, bool use_confidence, const std::string& source) {
  OrientedSamples s;
  const bool weighted = use_confidence && input.has_confidence();
  for (std::size_t i = 0; i < input.size(); ++i) {
    const Eigen::Vector3d n = input.normals[i].cast<double>();
    const double len = n.norm();
    if (!input.positions[i].allFinite() || !std::isfinite(len) || len == 0.0) {
      ++s.dropped_without_normal;
      continue;
    }
    s.points.push_back(input.positions[i]);
    s.normals.push_back((n / len).cast<float>());
    if (weighted) s.weights.push_back(std::isfinite(input.confidence[i]) ? std::max(0.0f, input.confidence[i]) : 0.0f);
  }
  if (s.points.empty()) throw InputError(source, "no point has a finite position and a usable normal");
  if (weighted && std::none_of(s.weights.begin(), s.weights.end(), [](float w) { return w > 0.0f; })) {
    throw InputError(source,
                     "property 'confidence' is 0 (or negative or NaN) at every point: nothing to weight the "
                     "orientations by; fix the input or set recon.use_confidence=false");
  }
  s.dropped_far = drop_far_outliers(s.points, s.normals, s.weights);
  const BoundingBox box = bounding_box(s.points);
  check_extent(box, source);
  s.frame.center = 0.5 * (box.min.cast<double>() + box.max.cast<double>());
  s.frame.scale = (box.max.cast<double>() - box.min.cast<double>()).maxCoeff();
  for (auto& p : s.points) p = ((p.cast<double>() - s.frame.center) / s.frame.scale).cast<float>();
  return s;
}

void to_world(const SampleFrame& frame, TriangleMesh& mesh) {
  for (auto& v : mesh.vertices) v = frame.to_world(v.cast<double>()).cast<float>();
}

}  // namespace hos::recon
