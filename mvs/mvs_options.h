// Options of the dense stereo stage, mapped 1:1 onto the "mvs:" YAML section.
#pragma once

#include <string>

namespace hos {
class OptionSet;
}

namespace hos::mvs {

struct MvsOptions {
  std::string backend = "cpu";   // cpu | colmap (COLMAP's CUDA PatchMatch, only when available)
  int max_image_size = 640;      // longest image side used for matching (2 cores: keep small)
  int num_source_views = 4;      // source views per reference view
  int best_k = 2;                // photo-consistency: mean of the best K source costs (occlusions)
  int window_radius = 4;         // matching window half size in pixels
  int window_step = 2;           // sample every step-th pixel of the window
  // PatchMatch sweeps (red-black, both colours). 4 instead of 3: the last
  // sweep's finer random refinement makes more pixels agree across views
  // (temple re-render +1.3 dB, synthetic F@1% +0.01, mvs time ~1.2x;
  // docs/mvs.md, "Fusion rules and sweeps").
  int iterations = 4;
  // Source views below this angle are not chosen; in fusion, agreeing views
  // closer than this to one already counted are no further evidence.
  double min_triangulation_angle_deg = 3.0;
  double max_cost = 0.6;         // 1 - NCC above this: pixel rejected
  double min_texture_std = 0.01; // window intensity std (0..1) below this: textureless, no depth
  double sigma_color = 0.2;      // bilateral weight: intensity scale
  // Geometric consistency and fusion.
  // Other views that must agree on depth and normal. 1 raised the synthetic
  // scene's completeness, but on real photos (Middlebury temple) it let in
  // noisy background and webs between columns: re-render PSNR 20.3 -> 18.4 dB
  // (docs/pipeline.md, "Accuracy of the defaults"). COLMAP's fusion asks more.
  int min_consistent_views = 2;
  // A point that only one other view confirms (surface seen by two photos:
  // sides, grazing views) is kept too when the matching cost (1 - NCC) of
  // both pixels is at most two_view_max_cost (0 = never) and at most
  // two_view_max_views_without_depth of the other views whose image covers
  // it have no depth there (a view that sees background or nothing
  // matchable at that spot speaks against the point). Synthetic F@1%
  // 0.90 -> 0.93 with the temple's re-render within 0.2 dB (docs/mvs.md).
  double two_view_max_cost = 0.6;
  int two_view_max_views_without_depth = 0;
  double max_depth_error = 0.01; // relative depth difference to agree
  double max_normal_error_deg = 20.0;
  double max_reprojection_error_px = 1.5;
  int threads = 0;               // OpenMP threads; 0 = all cores

  // Throws ConfigError naming the offending option.
  void validate() const;
};

void register_options(OptionSet& set, MvsOptions& options);

}  // namespace hos::mvs
