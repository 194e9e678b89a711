// The whole method of Pan & Skala on an oriented point set: domain and grid,
// orientation field (sec. 4.1), energy minimisation (sec. 3.4, 4.2, 4.3),
// isovalue (eq. 12), isosurface (sec. 4.4), then trimming.
#pragma once

#include <string>
#include <vector>

#include "core/reporter.h"
#include "core/types.h"
#include "recon/active_nodes.h"
#include "recon/debris.h"
#include "recon/domain.h"
#include "recon/grid.h"
#include "recon/recon_options.h"
#include "recon/sample_frame.h"

namespace hos::recon {

struct ReconStats {
  Eigen::Vector3i grid_dims = Eigen::Vector3i::Zero();
  double voxel_size = 0.0;
  int resolution = 0;  // cells along the domain's longest side (chosen, with recon.resolution 0)
  // Samples per cell that holds any, on the chosen grid, when it was chosen
  // from the density (0 otherwise).
  double samples_per_occupied_cell = 0.0;
  std::size_t num_samples = 0;
  std::size_t num_samples_dropped = 0;  // without a usable orientation
  int multigrid_levels = 0;
  int solver_iterations = 0;       // summed over all linear solves
  double relative_residual = 0.0;  // of the final linear solve (tiled: the largest of the tiles')
  // Relative residual after each iteration of every linear solve, in order
  // (the TV energy's reweighting rounds each start a new solve; tiled runs
  // list the tiles' solves in tile order).
  std::vector<double> residual_history;
  std::vector<int> solve_iterations;  // CG iterations of each linear solve, in order
  std::int64_t band_nodes = 0;        // fine nodes solved in the band; 0 = every node
  double isovalue = 0.0;
  std::size_t faces_before_trim = 0;
  std::size_t faces_trimmed = 0;  // far from every sample (trim.h)
  DebrisReport debris;            // pieces after trimming, and those removed (debris.h)
  double seconds_field = 0.0, seconds_solve = 0.0, seconds_mesh = 0.0;
  // Tiled runs (tiled_reconstruction.h): the tiles, the largest tile's solve
  // grid and the largest core (grown by one node) the join held, in nodes.
  int tiles = 1;
  std::int64_t largest_tile_nodes = 0;
  std::int64_t largest_join_nodes = 0;
};

struct ReconResult {
  TriangleMesh mesh;
  // The solved implicit function f on every node; its values stay empty when
  // the run kept only the band's (keeps_only_band).
  ScalarGrid function;
  ReconStats stats;
};

// Throws InputError(source, reason) when the points cannot be reconstructed:
// fewer than 4 points, no normals, all normals zero, an extent that is zero
// or below numerical resolution.
void check_reconstructable(const PointCloud& points, const std::string& source);

// The start of every run on input points (whole or tiled): the options
// validated, the points checked (check_reconstructable) and options.threads
// applied.
void begin_run(const PointCloud& input, const ReconOptions& options);

// Throws ConfigError for bad options, InputError for unusable points,
// NumericalError if the solve fails, Cancelled on request.
ReconResult reconstruct_surface(const PointCloud& input, const ReconOptions& options, Reporter& reporter);

// The last step of every run (whole or tiled), on the world-frame mesh:
// debris removed (remove_debris), result.stats.debris set, the removal reported.
void remove_debris_and_report(const DebrisOptions& options,
                              ReconResult& result,
                              Reporter& reporter,
                              const DebrisSupport& support = {});

// The samples reconstruct_surface works on (prepare_samples), the dropped
// ones counted in stats and reported.
OrientedSamples usable_samples(const PointCloud& input,
                               const ReconOptions& options,
                               ReconStats& stats,
                               Reporter& reporter);

// A run's grid and the options as its solve applies them, both in the unit
// frame of the samples: voxel_size and resolution as chosen, and with a grid
// from the samples' density the trim distance (and band_only_voxels) scaled.
struct RunGrid {
  GridGeometry grid;
  ReconOptions options;
};

// The grid of a run on samples (unit frame, usable_samples): from
// recon.voxel_size, recon.resolution, or with resolution 0 from the samples'
// density, then no finer than the memory budget allows when clamp_to_budget
// (a tiled run keeps the density's grid and cuts it into tiles instead).
// Sets stats' grid figures; reports the choice. Checks no budget otherwise.
RunGrid choose_run_grid(const OrientedSamples& samples,
                        const ReconOptions& options,
                        bool clamp_to_budget,
                        ReconStats& stats,
                        Reporter& reporter);

// A solved implicit function f and its isovalue.
struct ImplicitFunction {
  // On every node of the grid, or (keeps_only_band) on the band's stored nodes.
  StoredField f;
  double isovalue = 0.0;  // eq. 12: the mean of f at the samples
};

// The orientation field, energy minimisation and isovalue of
// reconstruct_surface on `grid`, for samples and options in the unit frame
// (usable_samples, choose_run_grid); the solver's figures and times go to
// stats. Allocates the grid without a memory check (check_memory_budget).
ImplicitFunction solve_implicit_function(const OrientedSamples& samples,
                                         const GridGeometry& grid,
                                         const ReconOptions& unit_options,
                                         ReconStats& stats,
                                         Reporter& reporter);

}  // namespace hos::recon
