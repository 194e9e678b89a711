#include "recon/memory_budget.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "recon/active_nodes.h"
#include "recon/domain.h"

namespace hos::recon {
namespace {

// Peak resident bytes, fitted to the peak RSS of hos-recon (/usr/bin/time) on
// spheres of 2 k, 240 k and 1.2 M points, 2 k scattered points and the
// bunny's scans at grids of 32 to 384 (docs/recon.md, "Memory"), rounded up
// so that the estimate is above every measurement.
//
// Whole grid (energy (2), recon.solver.band_voxels = 0, or a band that may
// not leave out half of the grid), per grid node: the orientation field, f,
// the right-hand side, the solver's vectors and the coarser multigrid levels;
// screening adds its per-level stencils, energy (2) its reweighting weights.
constexpr double kBytesPerNode = 64.0;
constexpr double kBytesPerNodeScreened = 80.0;
constexpr double kBytesPerNodeTotalVariation = 100.0;
// Band: per grid node the grid-sized arrays left, whose largest phase is the
// field's density and right-hand side (measured about 20 B/node) or, at the
// end, f with the band's result and the mesh; per stored band node the
// band's right-hand side and unknowns, the solver's vectors and the band's
// multigrid levels. The phases are added, not maxed: an upper bound.
constexpr double kBytesPerNodeBanded = 24.0;
constexpr double kBytesPerBandNode = 48.0;
// Band only (keeps_only_band): per stored band node bound, the fine band's
// solve in single precision (x, r, p, Ap and the V-cycle's result: 20 bytes
// per stored node, the peak), the coarser bands' V-cycle arrays and the
// screening term's cells; the bound is 1.3-1.7x the stored nodes. Fitted to
// the bunny's scans at grids 512 and 1024 and the 6-direction sphere at 1024
// (docs/recon.md, "Memory"), with the whole-grid level the solve starts on
// added (per node as a whole-grid run).
constexpr double kBytesPerBoundNodeBandOnly = 24.0;
// Per sample: the copies of the points, the trimming's search tree and, with
// screening, the per-level screening samples.
constexpr double kBytesPerSample = 128.0;
constexpr double kBytesPerSampleScreened = 256.0;
constexpr double kFixedBytes = 16.0 * 1024 * 1024;

// A byte count in double as size_t, saturating (a grid far beyond any
// machine must compare as too large, not wrap).
std::size_t saturated_bytes(double bytes) {
  constexpr double kMax = 0.5 * static_cast<double>(std::numeric_limits<std::size_t>::max());
  return bytes >= kMax ? static_cast<std::size_t>(kMax) : static_cast<std::size_t>(bytes);
}

// Would reconstruct_surface try a band on `grid` (see solve_with_bands)?
bool band_possible(const GridGeometry& grid, const ReconOptions& options) {
  return options.energy != SmoothnessEnergy::kTotalVariation && options.solver.band_voxels > 0 && grid.can_coarsen(3);
}

// An upper bound of the nodes within [c - r, c + 1 + r] per axis of some
// sample's cell corner c (the lower corner of the cell holding it), at most
// the grid's nodes. With blocks of b nodes per axis, a corner in block K
// reaches blocks K - ceil(r / b) to K + 1 + floor(r / b): those are marked
// around every block holding a corner, and their nodes counted.
std::int64_t nodes_near_samples_bound(const GridGeometry& grid, const std::vector<Eigen::Vector3f>& points, int r) {
  // Blocks of 4 nodes keep the bound within 1.32-1.38x of the stored band on
  // the sphere and the bunny (1.95x on isolated points); grids above 1024
  // nodes use larger blocks so that the block grid stays small.
  const Eigen::Vector3i& dims = grid.dims;
  const int b = std::max(4, (dims.maxCoeff() + 255) / 256);
  const int below = (r + b - 1) / b, above = 1 + r / b;
  const Eigen::Vector3i blocks = (dims.array() + b - 1) / b;
  const auto block_index = [&](int x, int y, int z) { return (std::int64_t{z} * blocks.y() + y) * blocks.x() + x; };
  std::vector<std::uint8_t> seeded(static_cast<std::size_t>(blocks.prod()), 0);
  std::vector<Eigen::Vector3i> seeds;
  for (const auto& p : points) {
    const Eigen::Vector3i corner = trilinear_stencil(grid, p.cast<double>()).corner;
    // Clamped: a sample outside the grid marks nothing, so this only adds.
    const Eigen::Vector3i block = (corner.array().max(0).min(dims.array() - 1) / b).matrix();
    std::uint8_t& s = seeded[block_index(block.x(), block.y(), block.z())];
    if (s == 0) seeds.push_back(block);
    s = 1;
  }
  std::vector<std::uint8_t> marked(seeded.size(), 0);
  std::int64_t nodes = 0;
  const auto nodes_along = [&](int axis, int block) { return std::min(b, dims[axis] - block * b); };
  for (const Eigen::Vector3i& seed : seeds) {
    const Eigen::Vector3i lo = (seed.array() - below).max(0).matrix();
    const Eigen::Vector3i hi = (seed.array() + above).min(blocks.array() - 1).matrix();
    for (int z = lo.z(); z <= hi.z(); ++z) {
      for (int y = lo.y(); y <= hi.y(); ++y) {
        for (int x = lo.x(); x <= hi.x(); ++x) {
          std::uint8_t& m = marked[block_index(x, y, z)];
          if (m != 0) continue;
          m = 1;
          nodes += std::int64_t{nodes_along(0, x)} * nodes_along(1, y) * nodes_along(2, z);
        }
      }
    }
  }
  return std::min(nodes, grid.num_nodes());
}

}  // namespace

// A sample marks the corners c and c + 1 of its cell (per axis); the band
// dilates them by `voxels` (the active nodes) and stores a halo of kHalo more.
std::int64_t band_active_nodes_bound(const GridGeometry& grid, const std::vector<Eigen::Vector3f>& points, int voxels) {
  return nodes_near_samples_bound(grid, points, std::max(voxels, 0));
}

std::int64_t band_stored_nodes_bound(const GridGeometry& grid, const std::vector<Eigen::Vector3f>& points, int voxels) {
  return nodes_near_samples_bound(grid, points, std::max(voxels, 0) + ActiveNodes::kHalo);
}

std::size_t estimate_peak_bytes(const GridGeometry& grid,
                                const std::vector<Eigen::Vector3f>& points,
                                const ReconOptions& options) {
  const double nodes = static_cast<double>(grid.num_nodes());
  const double per_sample = options.screening > 0.0 ? kBytesPerSampleScreened : kBytesPerSample;
  const double common = kFixedBytes + per_sample * static_cast<double>(points.size());
  double per_node = options.screening > 0.0 ? kBytesPerNodeScreened : kBytesPerNode;
  if (options.energy == SmoothnessEnergy::kTotalVariation) per_node = kBytesPerNodeTotalVariation;
  const double whole = common + per_node * nodes;
  if (!band_possible(grid, options)) return saturated_bytes(whole);
  if (keeps_only_band(grid, options)) {
    const double stored = static_cast<double>(band_stored_nodes_bound(grid, points, options.solver.band_only_voxels));
    GridGeometry start = grid;
    for (int l = band_only_start_level(grid); l > 0; --l) start = start.coarsened();
    const double start_bytes = kBytesPerNodeScreened * static_cast<double>(start.num_nodes());
    return saturated_bytes(common + start_bytes + kBytesPerBoundNodeBandOnly * stored);
  }
  const double stored = static_cast<double>(band_stored_nodes_bound(grid, points, options.solver.band_voxels));
  const double banded = common + kBytesPerNodeBanded * nodes + kBytesPerBandNode * stored;
  // The solve uses the band when its active nodes are at most half of the
  // grid (worthwhile_band): surely when their bound is (the stored nodes'
  // bound, when within half, bounds them too); above, either may be.
  if (2.0 * stored <= nodes ||
      2.0 * static_cast<double>(band_active_nodes_bound(grid, points, options.solver.band_voxels)) <= nodes) {
    return saturated_bytes(banded);
  }
  return saturated_bytes(std::max(whole, banded));
}

std::string megabytes(std::size_t bytes) {
  return std::to_string(static_cast<long long>(std::ceil(static_cast<double>(bytes) / (1024.0 * 1024.0)))) + " MB";
}

std::size_t memory_budget_bytes(const ReconOptions& options) {
  if (options.max_memory_mb > 0) return static_cast<std::size_t>(options.max_memory_mb) * 1024 * 1024;
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page_size = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return std::size_t{8} << 30;  // unknown: assume 8 GiB
  return static_cast<std::size_t>(0.75 * static_cast<double>(pages) * static_cast<double>(page_size));
}

int largest_resolution_within(const BoundingBox& box,
                              const std::vector<Eigen::Vector3f>& points,
                              const ReconOptions& options,
                              std::size_t budget) {
  ReconOptions trial = options;
  trial.voxel_size = 0.0;
  const auto fits = [&](int resolution) {
    trial.resolution = resolution;
    return estimate_peak_bytes(make_domain(box, trial), points, trial) <= budget;
  };
  int lo = kMinResolution, hi = kMaxResolution;
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

void check_memory_budget(const BoundingBox& box,
                         const std::vector<Eigen::Vector3f>& points,
                         const ReconOptions& options) {
  const std::size_t budget = memory_budget_bytes(options);
  const GridGeometry grid = make_domain(box, options);
  const std::size_t estimate = estimate_peak_bytes(grid, points, options);
  if (estimate <= budget) return;
  const int fitting = largest_resolution_within(box, points, options, budget);
  const std::string dims =
      std::to_string(grid.dims.x()) + "x" + std::to_string(grid.dims.y()) + "x" + std::to_string(grid.dims.z());
  std::string reason = "a " + dims + " grid needs about " + megabytes(estimate) + ", more than the budget of " +
                       megabytes(budget) + " (recon.max_memory_mb, --max-memory); ";
  reason += fitting > 0 ? "the largest resolution that fits is " + std::to_string(fitting)
                        : "not even the smallest grid fits";
  throw ConfigError(options.voxel_size > 0.0 ? "recon.voxel_size" : "recon.resolution", reason);
}

}  // namespace hos::recon
