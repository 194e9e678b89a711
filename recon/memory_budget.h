// Memory guard (issue item "estimate memory before allocating"): the peak
// memory of a reconstruction is estimated from the grid and the samples
// before anything grid-sized is allocated, and a resolution whose estimate
// exceeds the budget is refused with the largest resolution that fits.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/types.h"
#include "recon/grid.h"
#include "recon/recon_options.h"

namespace hos::recon {

// Upper bounds of the active nodes (ActiveNodes::count) and of the stored
// nodes (active and halo, storage_size) of the band of `voxels` voxels around
// `points` on `grid` (band_around_samples), found on blocks of nodes without
// a grid-sized array; at most the grid's nodes.
std::int64_t band_active_nodes_bound(const GridGeometry& grid, const std::vector<Eigen::Vector3f>& points, int voxels);
std::int64_t band_stored_nodes_bound(const GridGeometry& grid, const std::vector<Eigen::Vector3f>& points, int voxels);

// Estimated peak bytes of reconstruct_surface on `grid` with the oriented
// samples at `points` (field, solver with its multigrid hierarchy on the band
// or the whole grid, meshing).
std::size_t estimate_peak_bytes(const GridGeometry& grid,
                                const std::vector<Eigen::Vector3f>& points,
                                const ReconOptions& options);

// "N MB", N rounded up (for messages).
std::string megabytes(std::size_t bytes);

// recon.max_memory_mb in bytes, or, when it is 0, three quarters of the
// machine's physical memory.
std::size_t memory_budget_bytes(const ReconOptions& options);

// The largest recon.resolution whose estimate fits `budget` for `points`
// (whose bounding box is `box`), or 0 if not even the smallest grid fits.
int largest_resolution_within(const BoundingBox& box,
                              const std::vector<Eigen::Vector3f>& points,
                              const ReconOptions& options,
                              std::size_t budget);

// Throws ConfigError("recon.resolution" or "recon.voxel_size") naming the
// estimate, the budget and the largest resolution that fits when the grid for
// `box` (the bounding box of `points`) would exceed the budget.
void check_memory_budget(const BoundingBox& box,
                         const std::vector<Eigen::Vector3f>& points,
                         const ReconOptions& options);

}  // namespace hos::recon
