// Options of the dense stereo stage, mapped 1:1 onto the "mvs:" YAML section.
#pragma once

#include <string>

namespace hos {
class OptionSet;
}

namespace hos::mvs {

struct MvsOptions {
  std::string backend = "cpu";  // cpu | colmap (COLMAP's CUDA PatchMatch, only when available)
  // Matching size. Coarse to fine from 640 to 1280 px by default: on the
  // four Strecha hold-out photos it scored 0.38 dB (fountain-P11) and 0.17 dB
  // (Herz-Jesu-P8) above one level at 1024 px at 0.80-0.96x its mvs CPU
  // time, though it keeps fewer of the synthetic railing's bars
  // (docs/benchmarks-mvs.md). Levels double from coarse_image_size up to
  // max_image_size, each refined from the level below; max_image_size at
  // most coarse_image_size matches in one level.
  int max_image_size = 1280;    // longest image side of the finest level
  int coarse_image_size = 640;  // longest side of the full PatchMatch level; >= max_image_size: one level
  int num_source_views = 5;     // source views per reference view
  int best_k = 2;               // photo-consistency: mean of the best K source costs (occlusions)
  // The cost (1 - NCC) a source view counts with where it does not see the
  // window (outside its frame, behind it, on its mask): 1, no correlation,
  // lets a surface that only one source sees match; 2, the worst match,
  // needs best_k sources that see it (docs/benchmarks-mvs.md).
  double unseen_view_cost = 1.0;
  // Per-pixel view selection: after the coarse level's first sweep and
  // before each finer sweep, a pixel's candidates are scored on the sources
  // that score its current plane best, this many of them (0 = every source).
  // 3 took 0.78-0.88x the mvs CPU on the Strecha sets at no loss of
  // hold-out PSNR, but kept fewer of the synthetic railing's bars (0.746 ->
  // 0.638 at 1%; docs/benchmarks-mvs.md), so every source by default.
  int pixel_source_views = 0;
  int window_radius = 4;  // matching window half size in pixels
  int window_step = 2;    // sample every step-th pixel of the window
  int iterations = 4;     // coarse level sweeps (red-black, both colours)
  // Sweeps per finer level (they start from a converged plane); 2 scored
  // above 1 on the 1280x960 synthetic scene (docs/benchmarks-mvs.md).
  int refine_iterations = 2;
  // Finer levels: random planes a pixel the upsampled plane does not fit
  // tries before the sweeps, so thin structures the coarse level missed are
  // found (railing completeness at 1%, 640 -> 1280: 0.553 with none, 0.647
  // with 6).
  int refine_random_planes = 6;
  // Finer level: pixels whose upsampled plane costs at most this skip the sweeps (most of a smooth
  // surface).
  double refine_settled_cost = 0.15;
  double geometric_weight = 0.3;        // finer levels: cost of a plane the neighbours' coarse maps contradict
  double geometric_max_error_px = 2.0;  // reprojection error (coarse pixels) at which the weight is reached
  double detail_restore_margin = 0.15;  // a plane this much better photometrically outvotes the neighbours
  // Source views below this angle are not chosen; in fusion, agreeing views
  // closer than this to one already counted are no further evidence.
  double min_triangulation_angle_deg = 3.0;
  double source_view_angle_falloff_deg = 15.0;  // shared points at wider angles count less
  // Sources are chosen one at a time; a sparse point of the reference that
  // best_k sources chosen before see counts this much toward the next one,
  // so views that see the rest of the frame win (1 = rank by shared points).
  // 0.05 raised the synthetic ground's recall against the surface two
  // cameras see from 0.841 to 0.882 at the same CPU and left the Strecha
  // hold-outs' points unchanged, but re-rendered the Sceaux Castle photos
  // 0.06-0.34 dB lower over the pixels both runs cover, so the default
  // ranks (docs/benchmarks-mvs.md).
  double source_view_covered_weight = 1.0;
  // Planar prior (mvs/planar_prior.h): before the coarse level's last sweep,
  // pixels whose cost is above planar_prior_confident_cost also try the
  // plane of the triangle of confident pixels (cost at most that) they lie in.
  bool planar_prior = false;
  double planar_prior_confident_cost = 0.15;
  double max_cost = 0.6;           // 1 - NCC above this: pixel rejected
  double min_texture_std = 0.006;  // window intensity std (0..1) below this: textureless, no depth
  double sigma_color = 0.2;        // bilateral weight: intensity scale
  // Geometric consistency and fusion. Real photos need two other views to
  // agree: one lets noisy background and webs between columns in.
  int min_consistent_views = 2;
  // A point that only one other view confirms (sides, grazing views) is kept
  // when both pixels' cost (1 - NCC) is at most two_view_max_cost (0 = never)
  // and at most two_view_max_views_without_depth of the other views covering
  // it have no depth there (such a view speaks against the point). With
  // two_view_veto_max_incidence_deg below 180, a view that sees the point's
  // surface more grazingly does not: PatchMatch finds little depth at such
  // angles whether the surface is there or not. At 60 the synthetic scene's
  // undersides gain points, but real photos do not gain on balance
  // (docs/benchmarks-mvs.md), so every covering view counts by default.
  double two_view_max_cost = 0.6;
  int two_view_max_views_without_depth = 0;
  double two_view_veto_max_incidence_deg = 180.0;
  double max_depth_error = 0.01;  // relative depth difference to agree
  double max_normal_error_deg = 20.0;
  double max_reprojection_error_px = 1.5;  // in the pixels of the finest level
  // Density control with finer levels: a fused point claims the pixels
  // within this radius in every view that saw it, so a surface gets about
  // one point per (2r+1)^2 pixels of the finest level (one level: 0). Off by
  // default: recon's grid follows the points' density up to its limit, and
  // matching 1024 -> 2048 at radius 1 scored 0.7-0.8 dB below every pixel on
  // the Strecha hold-out photos (docs/benchmarks-mvs.md).
  int fusion_spacing_px = 0;
  // Streamed fusion: a view's depths are checked against the
  // fusion_max_views views sharing the most sparse points with it (0 = all;
  // as COLMAP's fusion checks a fixed number of overlapping images), and
  // fusion holds at most fusion_memory_mb of maps in memory (0 = all),
  // spilling the least recently used to a temporary folder. 50 synthetic
  // photos of 12 MP matched up to 2048 px peak at 1908 MB with these, 2375
  // MB with 1024 MB of maps, 3225 MB with every map in memory.
  int fusion_max_views = 20;
  int fusion_memory_mb = 512;
  int threads = 0;  // OpenMP threads; 0 = all cores

  // Throws ConfigError naming the offending option.
  void validate() const;
};

void register_options(OptionSet& set, MvsOptions& options);

}  // namespace hos::mvs
