#include "refine/refine_options.h"

#include "core/error.h"
#include "core/option_set.h"

namespace hos::refine {

void RefineOptions::validate() const {
  check_option_table("refine", *this);
  // The rules that involve two options.
  if (!(min_angle_deg < max_angle_deg)) throw ConfigError("refine.min_angle_deg", "must be below refine.max_angle_deg");
}

void register_options(OptionSet& set, RefineOptions& o) {
  set.add("enabled", o.enabled, "run the refinement (false: the recon mesh goes to texture as it is)");
  set.add_enum("regularizer", o.regularizer,
               {{"membrane", Regularizer::kMembrane}, {"thin_plate", Regularizer::kThinPlate}},
               "smoothness term: thin_plate (bi-Laplacian, keeps curved parts) or membrane (Laplacian)");
  set.add("lambda", o.lambda, "regulariser weight against the photometric targets", 0.0, 1e6);
  set.add("levels", o.levels, "image scales, coarse to fine (level l = 1/2^l of the photos)", 1, 6);
  set.add("min_level_size", o.min_level_size, "levels smaller than this (longest side, pixels) are not used", 16,
          100000);
  set.add("iterations", o.iterations, "refinement rounds per level", 0, 100);
  set.add("min_rounds", o.min_rounds,
          "at least this many rounds in all (the finest level adds them when fewer levels are usable)", 0, 100);
  set.add("edge_pixels", o.edge_pixels, "split edges longer than this many pixels of the level (0 = keep the faces)",
          0.0, 1000.0);
  set.add("max_faces", o.max_faces, "face budget of the subdivision", 1000, 100000000);
  set.add("search_steps", o.search_steps, "normal offsets tried on each side of a vertex", 1, 32);
  set.add("step_pixels", o.step_pixels, "spacing of the normal offsets, pixels of the reference view", 0.01, 100.0);
  set.add_odd("patch_size", o.patch_size, "matching patch side in samples (a window centred on the vertex)", 3, 15);
  set.add("sample_pixels", o.sample_pixels, "patch sample spacing, pixels of the reference view", 0.1, 20.0);
  set.add("min_patch_coverage", o.min_patch_coverage,
          "fraction of the patch's samples that must lie on the surface the reference view sees", 0.1, 1.0);
  set.add("search_spacing", o.search_spacing,
          "search vertices about this many pixels of the finest level apart, the rest take their targets (0 = all)",
          0.0, 100.0);
  set.add("coarse_search_spacing", o.coarse_search_spacing,
          "the same at the coarser levels, in pixels of each level (0 = every vertex)", 0.0, 100.0);
  set.add("max_views", o.max_views, "views compared with the reference view per vertex", 1, 64);
  set.add("min_angle_deg", o.min_angle_deg, "smallest angle between reference and compared view", 0.0, 89.0);
  set.add("max_angle_deg", o.max_angle_deg, "largest angle between reference and compared view", 1.0, 90.0);
  set.add("max_incidence_deg", o.max_incidence_deg, "views more grazing than this are not used", 1.0, 89.0);
  set.add("min_zncc", o.min_zncc, "best ZNCC below this gives the vertex no target", -1.0, 0.99);
  set.add("anchor_weight", o.anchor_weight, "weight holding each vertex where it is", 1e-6, 1e6);
  set.add("min_improvement", o.min_improvement, "stop a level when the mean score improves less", 0.0, 1.0);
  set.add("max_seconds", o.max_seconds, "time budget (s); the last finished round is kept", 0.1, 1e6);
  set.add("threads", o.threads, "OpenMP threads (0 = all cores)", 0, 1024);
  set.add_flag("--max-seconds", "max_seconds");
}

}  // namespace hos::refine
