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
  // Relative residual ||b - Ax|| / ||b|| to reach. Against 1e-4 the bunny's
  // level set moves by 0.0006-0.0026 voxel on average (grids 256-1024) and
  // its distance to the reference by under 0.3%, while 1e-4 takes about
  // twice the iterations (docs/recon.md, "Solver").
  double tolerance = 1e-3;
  int max_iterations = 200;  // conjugate-gradient iterations per linear solve
  int max_levels = 0;        // multigrid levels; 0 = as many as the grid allows
  // Degree of the Chebyshev smoother (operator applications) before and
  // after each coarse correction (see multigrid.h); 3 saves no iterations.
  int smoothing_steps = 2;
  int tv_iterations = 8;  // reweighting rounds for energy (2)
  bool multigrid = true;  // false: Jacobi-preconditioned CG (for comparisons)
  // Fine-grid nodes farther than this many voxels (per axis) from every
  // sample's cell keep the solution of the grid twice as coarse, and only the
  // band is solved at full resolution (see active_nodes.h). 0 = solve every node.
  // Wider bands cost nodes without changing the surface.
  int band_voxels = 6;
  // Grids of more nodes than this (in millions) keep no grid-sized array: the
  // right-hand side lives near the samples, each level's solution on its band
  // only, and the isosurface is extracted inside the band (see
  // reconstruct.cpp); 0 = always where the options allow it. Above grid
  // 256 (17 M nodes): on fountain-P11's points at grid 480 (51 M nodes) the
  // peak fell from 958 to 213 MB and the time by 25%.
  int band_storage_above_mnodes = 20;
  // The band's width (voxels) on such grids: narrower than band_voxels, since
  // the memory is the band's (bunny at 512: 17% less, the same distance to
  // the reference surface); at least trim.distance_voxels + 2.
  int band_only_voxels = 4;
};

// How the tiles of a tiled run meet (tiled_reconstruction.h).
enum class TileBlend {
  kSmooth,  // partition-of-unity weights, C1, across the overlaps
  kSwitch,  // each node from the tile whose core holds it (for comparisons)
};

struct TrimOptions {
  bool enabled = true;
  // Faces whose vertices all lie farther than this many voxels from every
  // sample are removed: the closed isosurface bridges areas without data.
  double distance_voxels = 2.0;
  // Around a sample with sparse but consistent support (recon/trim.h) the
  // distance is this many times longer (1 = off). 3 keeps 99% of a plane's
  // 25x sparser half (71% at 1) but costs precision at hos-synth's
  // silhouettes (docs/recon.md), so it is off by default.
  double sparse_reach = 1.0;
};

// Small pieces detached from the main surface (debris.h).
struct DebrisOptions {
  bool remove = true;
  // Pieces whose area is below this fraction of the largest piece's are
  // debris (docs/recon.md, "Debris": what the stray pieces measure).
  double min_area_fraction = 0.02;
  // A smaller piece stays when its samples' mean confidence (views agreeing
  // in fusion) is at least this (0 = off; debris.h).
  double keep_min_views = 3.0;
};

struct ReconOptions {
  SmoothnessEnergy energy = SmoothnessEnergy::kFullHessian;
  // Smoothness weight. Resolution independent: the Hessian term is weighted by
  // lambda * (D / 50)^2 (TV by lambda * D / 50) with D the domain's longest side,
  // so lambda = 0.2 damps features below about 1% of the domain at any grid size.
  double lambda = 0.2;
  // Cells along the longest side of the domain, in [kMinResolution,
  // kMaxResolution], or 0: the grid whose cells that hold samples hold
  // samples_per_cell of them on average (see sample_density.h), made
  // density_refinement times finer, within the memory budget.
  int resolution = 0;
  double samples_per_cell = 6.0;
  // Finer than the samples' density. With refine on, 1.5 scored 0.4-0.6 dB
  // higher than 1 in the Strecha sets' held-out photo and 1.0 dB lower in
  // hos-synth's scene (docs/recon.md); the preset "quality" sets 1.5.
  double density_refinement = 1.0;
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
  // Not used with energy (2). Strong enough that holes in MVS points are not
  // smoothed over.
  double screening = 16.0;
  SolverOptions solver;
  TrimOptions trim;
  DebrisOptions debris;
  int threads = 0;  // OpenMP threads; 0 = all cores
  // Memory budget in MB; a grid whose estimated peak exceeds it is cut into
  // tiles (tiles 0) or refused (tiles 1) before anything is allocated (see
  // memory_budget.h). 0 = 3/4 of the RAM.
  int max_memory_mb = 0;
  // Tiled reconstruction (tiled_reconstruction.h, docs/scale.md): the grid cut
  // into tiles solved one at a time and blended. 0 = only when the whole
  // grid's estimated peak exceeds the memory budget, into as few tiles as fit
  // (the density's grid is then kept, not made coarser); 1 = never (such a
  // grid is refused, or a density's grid made coarser); N >= 2: N tiles.
  int tiles = 0;
  // Voxels each tile reaches past its core into its neighbours' on every side
  // that has one, its function blended with theirs there. The bunny in 8
  // tiles (docs/scale.md): with 16 the seams were as close to the whole run
  // as the rest; at 2 their mean distance was 2.6 times the rest's.
  int tile_overlap_voxels = 16;
  TileBlend tile_blend = TileBlend::kSmooth;

  // Throws ConfigError naming the offending option.
  void validate() const;
};

// Registers every option under the section "recon".
void register_options(OptionSet& set, ReconOptions& options);

}  // namespace hos::recon
