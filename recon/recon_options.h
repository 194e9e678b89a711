// Options of the surface reconstruction, one struct per concern, each mapped
// 1:1 onto the "recon:" section of the YAML config by register_options.
#pragma once

#include <string>

namespace hos {
class OptionSet;
}

namespace hos::recon {

// recon.resolution's range (the option table's and the memory budget's).
constexpr int kMinResolution = 8;
constexpr int kMaxResolution = 2048;

// The smoothness energies of the paper, sec. 3.2.
enum class SmoothnessEnergy {
  kMembrane = 1,        // eq. (1): |grad f|^2
  kTotalVariation = 2,  // eq. (2): |grad f|
  kPureSecond = 3,      // eq. (3): fxx^2 + fyy^2 + fzz^2
  kFullHessian = 4,     // eq. (4): eq. (3) + 2 (fxy^2 + fxz^2 + fyz^2)
};

struct SolverOptions {
  // Relative residual ||b - Ax|| / ||b|| to reach. 1e-5 rather than 1e-6:
  // the same surface (sphere from 6 scan directions at grid 256: rms error
  // 4.1311e-4 vs 4.1309e-4) with 29 instead of 39 iterations.
  double tolerance = 1e-5;
  int max_iterations = 200;   // conjugate-gradient iterations per linear solve
  int max_levels = 0;         // multigrid levels; 0 = as many as the grid allows
  // Degree of the Chebyshev smoother (operator applications) before and
  // after each coarse correction (see multigrid.h). 2: the bunny's fine band
  // at grid 256 takes 9-10 CG iterations (1: 17, 3: 9).
  int smoothing_steps = 2;
  int tv_iterations = 8;      // reweighting rounds for energy (2)
  bool multigrid = true;      // false: Jacobi-preconditioned CG (for comparisons)
  // Fine-grid nodes farther than this many voxels (per axis) from every
  // sample's cell keep the solution of the grid twice as coarse, and only the
  // band is solved at full resolution (see active_nodes.h). 0 = solve every node.
  // 6 rather than 8: 22% fewer band nodes, the same surfaces (re-render of one
  // sfm and mvs result: temple 22.77 -> 22.78 dB, Herz-Jesu-P8 24.84 -> 24.83
  // dB; bunny mean distance to the reference 6.154e-5 -> 6.178e-5).
  int band_voxels = 6;
};

struct TrimOptions {
  bool enabled = true;
  // Faces whose vertices all lie farther than this many voxels from every
  // sample are removed: the closed isosurface bridges areas without data.
  double distance_voxels = 2.0;
  // Connected pieces with fewer faces than this fraction of the largest are dropped.
  double min_component_fraction = 0.01;
};

struct ReconOptions {
  SmoothnessEnergy energy = SmoothnessEnergy::kFullHessian;
  // Smoothness weight. Resolution independent: the Hessian term is weighted by
  // lambda * (D / 50)^2 (TV by lambda * D / 50) with D the domain's longest side,
  // so lambda = 0.2 damps features below about 1% of the domain at any grid size.
  double lambda = 0.2;
  // Cells along the longest side of the domain. 256: real photos keep thin
  // parts (temple columns), and with marching cubes' third of the triangles
  // 192 lost texture detail (re-render PSNR on one sfm and mvs result each,
  // 192 -> 256: temple 22.36 -> 22.78 dB, Herz-Jesu-P8 24.57 -> 24.84 dB);
  // recon stays small beside mvs (temple 1.5 -> 8 s against 69 s).
  int resolution = 256;        // in [kMinResolution, kMaxResolution]
  double voxel_size = 0.0;     // if > 0, overrides resolution
  double margin = 0.1;         // domain margin as a fraction of the points' longest extent
  int filter_passes = 3;       // box filter passes approximating a Gaussian (sec. 4.1)
  bool use_confidence = true;  // weight each orientation by the point's confidence
  // Field magnitude from the sample density, direction from the smoothed
  // orientations (see use_density_magnitude): robust to coarse orientations.
  bool uniform_flux = true;
  // Box filter passes for the orientations' directions when uniform_flux is
  // on: wider than the density's, so coarse per-scan orientations blend into
  // a smooth direction field while the flux stays concentrated at the samples.
  int direction_filter_passes = 12;
  // Weight of the screening term that pins f at the samples to the isovalue
  // (see Screening in energy_operator.h); 0 = the paper's pure formulation.
  // Not used with energy (2). 16 rather than 4: less smoothing across holes in
  // MVS points (synthetic scene F@1% 0.84 -> 0.93 with trim 2 and
  // mvs.min_consistent_views 1, docs/pipeline.md).
  double screening = 16.0;
  SolverOptions solver;
  TrimOptions trim;
  int threads = 0;  // OpenMP threads; 0 = all cores
  // Memory budget in MB; a grid whose estimated peak exceeds it is refused
  // before anything is allocated (see memory_budget.h). 0 = 3/4 of the RAM.
  int max_memory_mb = 0;

  // Throws ConfigError naming the offending option.
  void validate() const;
};

// Registers every option under the section "recon".
void register_options(OptionSet& set, ReconOptions& options);

}  // namespace hos::recon
