#include "recon/memory_budget.h"

#include <unistd.h>

#include <cmath>

#include "core/error.h"
#include "recon/reconstruct.h"

namespace hos::recon {
namespace {

// Peak resident bytes per grid node and per sample, fitted to the peak RSS of
// hos-recon (/usr/bin/time) on spheres of 240 k and 1.2 M points at grids of
// 64, 128 and 192 (docs/recon.md, "Memory"), rounded up. The node term covers
// the orientation field, f, the right-hand side, the solver's vectors and the
// coarser multigrid levels; screening adds its per-level stencils, energy (2)
// its reweighting weights; the sample term the copies of the points, the
// per-level screening samples and the trimming's search tree.
constexpr double kBytesPerNode = 64.0;
constexpr double kBytesPerNodeScreened = 80.0;
constexpr double kBytesPerNodeTotalVariation = 84.0;
constexpr double kBytesPerSample = 500.0;
constexpr double kFixedBytes = 64.0 * 1024 * 1024;

std::string megabytes(std::size_t bytes) {
  return std::to_string(static_cast<long long>(std::llround(static_cast<double>(bytes) / (1024.0 * 1024.0)))) + " MB";
}

}  // namespace

std::size_t estimate_peak_bytes(const GridGeometry& grid, std::size_t num_samples, const ReconOptions& options) {
  const double nodes = static_cast<double>(grid.num_nodes());
  double per_node = options.screening > 0.0 ? kBytesPerNodeScreened : kBytesPerNode;
  if (options.energy == SmoothnessEnergy::kTotalVariation) per_node = kBytesPerNodeTotalVariation;
  return static_cast<std::size_t>(kFixedBytes + per_node * nodes + kBytesPerSample * static_cast<double>(num_samples));
}

std::size_t memory_budget_bytes(const ReconOptions& options) {
  if (options.max_memory_mb > 0) return static_cast<std::size_t>(options.max_memory_mb) * 1024 * 1024;
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page_size = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return std::size_t{8} << 30;  // unknown: assume 8 GiB
  return static_cast<std::size_t>(0.75 * static_cast<double>(pages) * static_cast<double>(page_size));
}

int largest_resolution_within(const BoundingBox& box, std::size_t num_samples, const ReconOptions& options,
                              std::size_t budget) {
  ReconOptions trial = options;
  trial.voxel_size = 0.0;
  const auto fits = [&](int resolution) {
    trial.resolution = resolution;
    return estimate_peak_bytes(make_domain(box, trial), num_samples, trial) <= budget;
  };
  int lo = 8, hi = 2048;  // recon.resolution's range
  if (!fits(lo)) return 0;
  while (lo < hi) {  // the estimate grows with the resolution: bisect
    const int mid = (lo + hi + 1) / 2;
    if (fits(mid)) {
      lo = mid;
    } else {
      hi = mid - 1;
    }
  }
  return lo;
}

void check_memory_budget(const BoundingBox& box, std::size_t num_samples, const ReconOptions& options) {
  const std::size_t budget = memory_budget_bytes(options);
  const GridGeometry grid = make_domain(box, options);
  const std::size_t estimate = estimate_peak_bytes(grid, num_samples, options);
  if (estimate <= budget) return;
  const int fitting = largest_resolution_within(box, num_samples, options, budget);
  const std::string dims = std::to_string(grid.dims.x()) + "x" + std::to_string(grid.dims.y()) + "x" +
                           std::to_string(grid.dims.z());
  std::string reason = "a " + dims + " grid needs about " + megabytes(estimate) + ", more than the budget of " +
                       megabytes(budget) + " (recon.max_memory_mb, --max-memory); ";
  reason += fitting > 0 ? "the largest resolution that fits is " + std::to_string(fitting)
                        : "not even the smallest grid fits";
  throw ConfigError(options.voxel_size > 0.0 ? "recon.voxel_size" : "recon.resolution", reason);
}

}  // namespace hos::recon
