#include "recon/sample_density.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "recon/domain.h"

namespace hos::recon {

double mean_samples_per_occupied_cell(const BoundingBox& box,
                                      const std::vector<Eigen::Vector3f>& points,
                                      const ReconOptions& options,
                                      int resolution) {
  if (points.empty()) return 0.0;
  ReconOptions trial = options;
  trial.voxel_size = 0.0;
  trial.resolution = resolution;
  const GridGeometry g = make_domain(box, trial);
  std::vector<std::int64_t> cells;
  cells.reserve(points.size());
  for (const Eigen::Vector3f& p : points) {
    std::int64_t key = 0;
    for (int a = 0; a < 3; ++a) {
      const double c = std::floor((static_cast<double>(p[a]) - g.origin[a]) / g.spacing);
      key = key * g.dims[a] + std::clamp<std::int64_t>(static_cast<std::int64_t>(c), 0, g.dims[a] - 1);
    }
    cells.push_back(key);
  }
  std::sort(cells.begin(), cells.end());
  const auto occupied = std::unique(cells.begin(), cells.end()) - cells.begin();
  return static_cast<double>(points.size()) / static_cast<double>(occupied);
}

int resolution_from_density(const BoundingBox& box,
                            const std::vector<Eigen::Vector3f>& points,
                            const ReconOptions& options) {
  const auto dense_enough = [&](int resolution) {
    return mean_samples_per_occupied_cell(box, points, options, resolution) >= options.samples_per_cell;
  };
  // The mean falls as the grid refines (up to the grids not nesting): bisect
  // on a step of 8 cells, finer than the rule's own precision.
  constexpr int kStep = 8;
  int lo = kMinDensityResolution / kStep, hi = kMaxDensityResolution / kStep;
  if (!dense_enough(lo * kStep)) return kMinDensityResolution;
  while (lo < hi) {
    const int mid = (lo + hi + 1) / 2;
    if (dense_enough(mid * kStep)) {
      lo = mid;
    } else {
      hi = mid - 1;
    }
  }
  return lo * kStep;
}

}  // namespace hos::recon
