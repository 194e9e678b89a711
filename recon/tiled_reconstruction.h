// Tiled reconstruction (docs/scale.md, "Design: tiled reconstruction"), for
// grids that do not fit one machine's memory: the whole run's grid is cut
// into tiles (tile_plan.h), each solved alone from the samples of its
// extended box at the whole run's voxel size, its f normalised to an
// approximate signed distance g = (f - iso) / s (iso of eq. 12, s the median
// |grad f| at the samples in its core), written to a file per tile
// (tile_function_file.h). The join blends the tiles' g with partition-of-unity
// weights core by core (never holding the whole grid: a core and the parts
// of its neighbours' files that reach into it), extracts each core's surface
// at g = 0 (sec. 4.4), welds the vertices that adjacent cores share on their
// common faces, and trims as recon does. The tiles are independent, so a
// cluster solves them as separate jobs (hos-recon --tile K) and one job joins
// them (--join-tiles); the result is the same bytes as one process's.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "core/reporter.h"
#include "core/types.h"
#include "recon/reconstruct.h"
#include "recon/tile_plan.h"

namespace hos::recon {

// What every process of a tiled run computes alike from the points and the
// options.
struct TiledRun {
  OrientedSamples samples;  // all usable points, in their unit frame
  TilePlan plan;
  std::uint64_t fingerprint = 0;  // tiled_run_fingerprint
  ReconStats stats;               // the whole run's grid and samples
};

// The samples, the whole run's grid (recon.resolution, recon.voxel_size or
// the samples' density, not made coarser for the budget) and the tile plan:
// recon.tiles tiles, or with 0 as many as recon.max_memory_mb needs (one
// when the whole grid fits). Throws what reconstruct_surface throws for bad
// points and options, ConfigError when the tiles cannot be cut that small.
TiledRun prepare_tiled_run(const PointCloud& input, const ReconOptions& options, Reporter& reporter);

// FNV-1a over the samples, the options, the lattice and every tile's boxes:
// tile files of another run are refused.
std::uint64_t tiled_run_fingerprint(const OrientedSamples& samples, const TilePlan& plan);

// The median of |grad f| at points (central differences of the trilinear
// interpolant, step one voxel), the scale that makes f - iso an approximate
// signed distance; 1 without points.
double median_gradient_magnitude(const GridGeometry& g,
                                 const StoredField& f,
                                 const std::vector<Eigen::Vector3f>& points);

// The distance, in voxels, of a world point to the nearest face between its
// core and another (a seam); infinite with one tile or outside the grid.
double voxels_to_seam(const TiledRun& run, const Eigen::Vector3f& world);

struct TileSolveReport {
  std::int64_t grid_nodes = 0;  // of the tile's solve grid
  std::size_t num_samples = 0;  // in its extended box
  double isovalue = 0.0, gradient_scale = 1.0;
  ReconStats stats;  // the solve's figures
};

// Solves tile k of the run alone and writes its normalised function to
// tile_function_file(dir, k). A tile of fewer than 4 samples has no
// function (every value NaN). Throws ConfigError when k is not a tile of
// the plan or the tile's estimated peak exceeds the memory budget.
TileSolveReport solve_tile(const TiledRun& run, int k, const std::filesystem::path& dir, Reporter& reporter);

// Blends the tiles' functions of dir core by core, extracts, welds and trims
// the surface (in world units; ReconResult::function stays empty), then
// removes debris as reconstruct_surface does (input, the points the run was
// prepared from, keeps small pieces its confident samples support). Throws
// InputError naming a tile file that is missing, truncated or foreign,
// NumericalError when the surface is empty.
ReconResult join_tiles(const TiledRun& run,
                       const PointCloud& input,
                       const std::filesystem::path& dir,
                       Reporter& reporter);

// reconstruct_surface, or, when recon.tiles asks for tiles or (tiles 0) the
// whole grid exceeds the memory budget, every tile solved in turn into dir
// and joined (the log says so). The tile files stay in dir.
ReconResult reconstruct_with_tiles(const PointCloud& input,
                                   const ReconOptions& options,
                                   const std::filesystem::path& dir,
                                   Reporter& reporter);

}  // namespace hos::recon
