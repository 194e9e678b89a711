// Memory guard (issue item "estimate memory before allocating"): the peak
// memory of a reconstruction is estimated from the grid and the sample count
// before anything grid-sized is allocated, and a resolution whose estimate
// exceeds the budget is refused with the largest resolution that fits.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/types.h"
#include "recon/grid.h"
#include "recon/recon_options.h"

namespace hos::recon {

// Estimated peak bytes of reconstruct_surface on `grid` with `num_samples`
// oriented points (field, solver with its multigrid hierarchy, meshing).
std::size_t estimate_peak_bytes(const GridGeometry& grid, std::size_t num_samples, const ReconOptions& options);

// recon.max_memory_mb in bytes, or, when it is 0, three quarters of the
// machine's physical memory.
std::size_t memory_budget_bytes(const ReconOptions& options);

// The largest recon.resolution whose estimate fits `budget` for points in
// `box`, or 0 if not even the smallest grid fits.
int largest_resolution_within(const BoundingBox& box, std::size_t num_samples, const ReconOptions& options,
                              std::size_t budget);

// Throws ConfigError("recon.resolution" or "recon.voxel_size") naming the
// estimate, the budget and the largest resolution that fits when the grid for
// `box` would exceed the budget.
void check_memory_budget(const BoundingBox& box, std::size_t num_samples, const ReconOptions& options);

}  // namespace hos::recon
