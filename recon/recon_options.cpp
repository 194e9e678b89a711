#include "recon/recon_options.h"

#include "core/option_set.h"

namespace hos::recon {

void ReconOptions::validate() const { check_option_table("recon", *this); }

void register_options(OptionSet& set, ReconOptions& o) {
  set.add_enum("energy", o.energy,
               {{"1", SmoothnessEnergy::kMembrane},
                {"2", SmoothnessEnergy::kTotalVariation},
                {"3", SmoothnessEnergy::kPureSecond},
                {"4", SmoothnessEnergy::kFullHessian}},
               "smoothness energy of Pan & Skala: 1 membrane, 2 total variation, 3 pure second "
               "derivatives, 4 full Hessian");
  set.add("lambda", o.lambda, "smoothness weight (resolution independent; paper range 0.1-0.3)", 0.0, 1e6);
  set.add_zero_or("resolution", o.resolution,
                  "grid cells along the longest side of the domain (0 = from the samples' density: see "
                  "samples_per_cell and density_refinement)",
                  kMinResolution, kMaxResolution);
  set.add("samples_per_cell", o.samples_per_cell,
          "with resolution 0: the density's grid is the finest whose cells that hold samples hold this many on average",
          1.0, 1000.0);
  set.add("density_refinement", o.density_refinement,
          "with resolution 0: the grid is this many times finer than the density's (trim distances keep their length)",
          0.25, 8.0);
  set.add("voxel_size", o.voxel_size, "grid spacing in scene units; 0 = use resolution", 0.0, 1e12);
  set.add("margin", o.margin, "domain margin around the points, fraction of their extent", 0.0, 2.0);
  set.add("filter_passes", o.filter_passes, "box filter passes smoothing the orientation field", 0, 10);
  set.add("uniform_flux", o.uniform_flux, "field magnitude from the sample density, direction from the orientations");
  set.add("direction_filter_passes", o.direction_filter_passes,
          "box filter passes for the orientations' directions (with uniform_flux)", 0, 100);
  set.add("screening", o.screening, "weight pinning f at the samples to the isovalue (0 = off)", 0.0, 1000.0);
  set.add("use_confidence", o.use_confidence, "weight orientations by the points' confidence");
  set.add("solver.tolerance", o.solver.tolerance, "relative residual the solver must reach", 1e-12, 0.5);
  set.add("solver.max_iterations", o.solver.max_iterations, "CG iterations per linear solve", 1, 100000);
  set.add("solver.max_levels", o.solver.max_levels, "multigrid levels (0 = automatic)", 0, 16);
  set.add("solver.smoothing_steps", o.solver.smoothing_steps,
          "Chebyshev smoother degree per level (operator applications)", 1, 20);
  set.add("solver.tv_iterations", o.solver.tv_iterations, "reweighting rounds for energy 2", 1, 100);
  set.add("solver.multigrid", o.solver.multigrid, "multigrid-preconditioned CG (false: Jacobi-preconditioned CG)");
  set.add("solver.band_voxels", o.solver.band_voxels,
          "solve the fine grid only this many voxels around the samples (0 = everywhere)", 0, 1 << 20);
  set.add("solver.band_storage_above_mnodes", o.solver.band_storage_above_mnodes,
          "grids above this many million nodes keep values only near the samples (0 = always)", 0, 1 << 20);
  set.add("solver.band_only_voxels", o.solver.band_only_voxels,
          "band width (voxels) when keeping values only near the samples; at least trim.distance_voxels + 2", 1,
          1 << 20);
  set.add("trim.enabled", o.trim.enabled, "remove surface far from every sample");
  set.add("trim.distance_voxels", o.trim.distance_voxels,
          "trim distance in voxels (with resolution 0: voxels of the density's grid)", 0.1, 1000.0);
  set.add("trim.sparse_reach", o.trim.sparse_reach,
          "around samples with sparse but consistent support the trim distance is this many times longer (1 = off)",
          1.0, 10.0);
  set.add("debris.remove", o.debris.remove,
          "remove small pieces detached from the main surface (false: keep every piece)");
  set.add("debris.min_area_fraction", o.debris.min_area_fraction,
          "pieces whose area is below this fraction of the largest piece's are debris", 0.0, 1.0);
  set.add("debris.keep_min_views", o.debris.keep_min_views,
          "a smaller piece stays when its samples' mean confidence (views agreeing in fusion) is at least this (0 = "
          "off)",
          0.0, 1000.0);
  set.add("threads", o.threads, "OpenMP threads (0 = all cores)", 0, 1024);
  set.add("max_memory_mb", o.max_memory_mb,
          "memory budget (MB): a larger grid is cut into tiles, or with tiles 1 refused, before allocating (0 = 3/4 "
          "of the RAM)",
          0, 1 << 30);
  set.add("tiles", o.tiles,
          "tiles the grid is cut into (0 = as many as the memory budget needs, 1 = never tile, N = N tiles)", 0, 4096);
  set.add("tile_overlap_voxels", o.tile_overlap_voxels,
          "voxels a tile reaches into its neighbours' cores, where their functions are blended", 1, 1 << 16);
  set.add_enum("tile_blend", o.tile_blend, {{"smooth", TileBlend::kSmooth}, {"switch", TileBlend::kSwitch}},
               "how tiles meet: smooth (C1 weights across the overlaps) or switch (hard, at the cores' faces; "
               "for comparisons)");
  set.add_flag("--energy", "energy");
  set.add_flag("--lambda", "lambda");
  set.add_flag("--resolution", "resolution");
  set.add_flag("--voxel-size", "voxel_size");
  set.add_flag("--max-memory", "max_memory_mb");
  set.add_flag("--no-trim", "trim.enabled", "false");
  set.add_flag("--keep-debris", "debris.remove", "false");
}

}  // namespace hos::recon
