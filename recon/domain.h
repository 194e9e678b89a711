// A run's domain: the grid for the points' bounding box (margin, cubic
// cells, dims that coarsen enough for the multigrid levels) and whether a
// run on a grid keeps only the band near the samples.
#pragma once

#include "core/types.h"
#include "recon/grid.h"
#include "recon/recon_options.h"

namespace hos::recon {

// Nodes per axis beyond which a domain is not made larger: far more than
// any machine holds, small enough that node counts stay exact in int64.
inline constexpr int kMaxDomainNodes = 1 << 20;

// The grid for the points' bounding box: margin, cubic cells, dims that
// coarsen at least levels - 1 times (at most about kMaxDomainNodes). levels 0:
// 5, and one more per doubling of the longest axis beyond 600 nodes, so that
// the whole grid a banded solve starts on (band_only_start_level) still has
// its multigrid levels.
GridGeometry make_domain(const BoundingBox& box, const ReconOptions& options, int levels = 0);

// The multigrid levels make_domain gives a grid whose longest side has this
// many nodes: 5, and one more per doubling beyond 600 (at most 12).
int domain_levels(double longest_nodes);

// Does a run on this grid keep no grid-sized array (recon.solver.
// band_storage_above_mnodes)? That needs a banded solve of a quadratic
// energy, the field near the samples, and trimming that removes every face
// outside the band's cells (a face within trim.distance_voxels of a sample
// lies in cells within distance_voxels + 2 nodes of its cell's corners, so
// recon.solver.band_only_voxels must reach that far).
bool keeps_only_band(const GridGeometry& grid, const ReconOptions& options);

// With keeps_only_band, the banded solve starts on the grid coarsened this
// many times, solved whole: twice, and more while that grid has over 2^22
// nodes.
int band_only_start_level(const GridGeometry& grid);

}  // namespace hos::recon
