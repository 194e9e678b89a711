// Result surface (mesh or points) against a ground-truth mesh: accuracy,
// completeness, Chamfer distance and precision/recall/F-score at thresholds
// given as fractions of the truth's bounding-box diagonal.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/reporter.h"
#include "core/types.h"

namespace hos::eval {

// n points uniformly distributed by area over the mesh (a face is picked with
// probability proportional to its area, then a uniform barycentric point), from
// a fixed seed: the same call gives the same points on every machine.
// Throws NumericalError for a mesh of zero total area.
std::vector<Eigen::Vector3f> sample_surface_uniform(const TriangleMesh& mesh, std::size_t n, std::uint64_t seed);

struct SurfaceDistanceOptions {
  std::size_t num_samples = 200000;  // per surface
  std::uint64_t seed = 1;
  // Thresholds as fractions of the truth's bounding-box diagonal.
  std::vector<double> thresholds = {0.005, 0.01, 0.02};
  void validate() const;  // throws ConfigError
};

struct DistanceStats {
  double mean = 0.0, median = 0.0, p90 = 0.0, rms = 0.0, max = 0.0;
  std::size_t count = 0;
};
DistanceStats summarize_distances(std::vector<double> distances);

struct ThresholdScore {
  double fraction = 0.0;   // of the truth diagonal
  double distance = 0.0;   // absolute
  double precision = 0.0;  // fraction of result samples within distance of the truth
  double recall = 0.0;     // fraction of truth samples within distance of the result
  double f_score = 0.0;    // 2PR / (P + R), 0 when both are 0
};

struct SurfaceComparison {
  double truth_diagonal = 0.0;
  bool result_is_points = false;
  DistanceStats accuracy;      // result -> truth
  DistanceStats completeness;  // truth -> result
  double chamfer = 0.0;        // (accuracy.mean + completeness.mean) / 2
  std::vector<ThresholdScore> scores;
  // The middle entry of scores (1% with the default thresholds).
  const ThresholdScore& primary() const { return scores[scores.size() / 2]; }
};

// Accuracy samples the result mesh and measures exact point-to-triangle
// distances to the truth; completeness samples the truth and measures to the
// result. A result without faces is a point set: its points are used as they
// are and completeness measures to the nearest point (k-d tree).
SurfaceComparison compare_surfaces(const TriangleMesh& result,
                                   const TriangleMesh& truth,
                                   const SurfaceDistanceOptions& options,
                                   Reporter& reporter);

// Exact distance from every point to the mesh (OpenMP).
std::vector<double> distances_to_mesh(const std::vector<Eigen::Vector3f>& points,
                                      const TriangleMesh& mesh,
                                      Reporter& reporter);

// Distances from n samples of `from` (sample_surface_uniform, seed) to `to`,
// split by where the sample lies: in_zone's samples, then the others (e.g.
// near the seams of a tiled reconstruction against the rest).
struct ZoneDistances {
  DistanceStats in_zone, rest;
};
ZoneDistances distances_by_zone(const TriangleMesh& from,
                                const TriangleMesh& to,
                                std::size_t n,
                                std::uint64_t seed,
                                const std::function<bool(const Eigen::Vector3f&)>& in_zone,
                                Reporter& reporter);

}  // namespace hos::eval
