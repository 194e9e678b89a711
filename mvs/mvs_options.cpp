#include "mvs/mvs_options.h"

#include "core/error.h"
#include "core/option_set.h"

namespace hos::mvs {

void MvsOptions::validate() const {
  check_option_table("mvs", *this);
  if (window_step > window_radius) throw ConfigError("mvs.window_step", "must be at most mvs.window_radius");
  if (pixel_source_views != 0 && pixel_source_views < best_k) {
    throw ConfigError("mvs.pixel_source_views", "must be 0 or at least mvs.best_k");
  }
}

namespace {

// Geometric consistency and fusion.
void register_fusion_options(OptionSet& set, MvsOptions& o) {
  set.add("min_consistent_views", o.min_consistent_views, "views that must agree for a point to survive", 1, 32);
  set.add("two_view_max_cost", o.two_view_max_cost,
          "also keep points one other view confirms when both pixels' cost (1 - NCC) is at most "
          "this (0 = never)",
          0.0, 2.0);
  set.add("two_view_max_views_without_depth", o.two_view_max_views_without_depth,
          "two-view points: other views covering the point that may have no depth there", 0, 1024);
  set.add("two_view_veto_max_incidence_deg", o.two_view_veto_max_incidence_deg,
          "two-view points: a covering view without depth counts only if it sees the point's surface at "
          "most this far from head-on (degrees; 180 = every covering view)",
          0.0, 180.0);
  set.add("max_depth_error", o.max_depth_error, "relative depth difference to agree", 1e-4, 0.5);
  set.add("max_normal_error_deg", o.max_normal_error_deg, "normal angle difference to agree (degrees)", 1.0, 90.0);
  set.add("max_reprojection_error_px", o.max_reprojection_error_px,
          "forward-backward reprojection error to agree (pixels)", 0.1, 20.0);
  set.add("fusion_spacing_px", o.fusion_spacing_px,
          "with finer levels, a fused point claims the pixels within this radius in the views "
          "that saw it (0 = every pixel)",
          0, 16);
  set.add("fusion_max_views", o.fusion_max_views,
          "fusion checks a view's depths against this many views sharing the most sparse points with "
          "it (0 = all)",
          0, 100000);
  set.add("fusion_memory_mb", o.fusion_memory_mb,
          "depth maps fusion holds in memory (MB); the rest wait in a temporary folder (0 = no limit)", 0, 1 << 24);
}

}  // namespace

void register_options(OptionSet& set, MvsOptions& o) {
  set.add_choice("backend", o.backend, {"cpu", "colmap"},
                 "cpu: hos PatchMatch; colmap: COLMAP's patch_match_stereo (needs CUDA)");
  set.add("max_image_size", o.max_image_size, "longest image side of the finest matching level", 64, 16384);
  set.add("coarse_image_size", o.coarse_image_size,
          "longest image side of the full PatchMatch level (levels double up to max_image_size)", 64, 16384);
  set.add("num_source_views", o.num_source_views, "source views per reference view", 1, 32);
  set.add("best_k", o.best_k, "photo-consistency: mean of the best K source views", 1, 32);
  set.add("unseen_view_cost", o.unseen_view_cost,
          "the cost (1 - NCC) a source view counts with where the window leaves its frame or falls on its mask "
          "(1 = no correlation; 2 = the worst match: a surface needs best_k sources that see it)",
          0.0, 2.0);
  set.add("pixel_source_views", o.pixel_source_views,
          "sweeps after the first score a pixel's candidates on the sources that score its plane best, this "
          "many (0 = every source; at least best_k)",
          0, 32);
  set.add("window_radius", o.window_radius, "matching window half size (pixels)", 1, 15);
  set.add("window_step", o.window_step, "window sampling step (pixels)", 1, 15);
  set.add("iterations", o.iterations, "PatchMatch sweeps at the coarse level", 1, 20);
  set.add("refine_iterations", o.refine_iterations, "sweeps per finer level", 0, 20);
  set.add("refine_random_planes", o.refine_random_planes,
          "finer levels: random planes a pixel not settled tries before the sweeps (finds thin structures)", 0, 64);
  set.add("refine_settled_cost", o.refine_settled_cost,
          "finer levels: pixels whose upsampled plane costs (1 - NCC) at most this skip the sweeps", 0.0, 2.0);
  set.add("geometric_weight", o.geometric_weight,
          "finer levels: cost per view of a plane the neighbours' coarse depth maps contradict", 0.0, 2.0);
  set.add("geometric_max_error_px", o.geometric_max_error_px,
          "reprojection error (coarse pixels) at which a view's geometric cost reaches "
          "geometric_weight",
          0.1, 20.0);
  set.add("detail_restore_margin", o.detail_restore_margin,
          "a plane whose matching cost is lower by this keeps its place against the geometric vote", 0.0, 2.0);
  set.add("min_triangulation_angle_deg", o.min_triangulation_angle_deg,
          "smallest triangulation angle of a source view, and between views counted as agreeing in "
          "fusion",
          0.0, 60.0);
  set.add("source_view_angle_falloff_deg", o.source_view_angle_falloff_deg,
          "source views: a shared sparse point's weight falls off as a Gaussian of this width beyond 5x "
          "min_triangulation_angle_deg, so neighbours win over wide baselines that see the surface "
          "foreshortened differently (0 = no falloff)",
          0.0, 90.0);
  set.add("source_view_covered_weight", o.source_view_covered_weight,
          "sources are chosen one at a time; a sparse point of the reference that best_k sources chosen "
          "before see counts this much toward the next (1 = rank by shared points alone)",
          0.01, 1.0);
  set.add("planar_prior", o.planar_prior,
          "before the coarse level's last sweep, unconfident pixels also try the plane of the triangle of "
          "confident pixels they lie in");
  set.add("planar_prior_confident_cost", o.planar_prior_confident_cost,
          "planar prior: pixels whose cost (1 - NCC) is at most this span the triangles; the others try them", 0.0,
          2.0);
  set.add("max_cost", o.max_cost, "largest accepted matching cost (1 - NCC)", 0.0, 2.0);
  set.add("min_texture_std", o.min_texture_std, "window intensity std below which a pixel is textureless", 0.0, 1.0);
  set.add("sigma_color", o.sigma_color, "bilateral weight intensity scale", 1e-3, 10.0);
  register_fusion_options(set, o);
  set.add("threads", o.threads, "OpenMP threads (0 = all cores)", 0, 1024);
  set.add_flag("--max-image-size", "max_image_size");
}

}  // namespace hos::mvs
