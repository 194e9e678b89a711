#include "sfm/sfm_options.h"

#include "core/error.h"
#include "core/option_set.h"

namespace hos::sfm {

void SfmOptions::validate() const {
  check_option_table("sfm", *this);
  if (max_image_size != 0 && max_image_size < min_image_size) {
    throw ConfigError("sfm.max_image_size", "value " + std::to_string(max_image_size) +
                                                " must be 0 (off) or at least sfm.min_image_size (" +
                                                std::to_string(min_image_size) + ")");
  }
}

void register_options(OptionSet& set, SfmOptions& o) {
  set.add("colmap", o.colmap, "COLMAP executable (name on PATH or path); $HOS_COLMAP replaces the default");
  set.add_choice("camera_model", o.camera_model,
                 {"SIMPLE_PINHOLE", "PINHOLE", "SIMPLE_RADIAL", "RADIAL", "OPENCV"},
                 "COLMAP camera model estimated by the mapper");
  set.add_choice("camera_mode", o.camera_mode, {"auto", "single", "per_image"},
                 "auto: one camera if all photos share size and EXIF focal length");
  set.add_choice("matcher", o.matcher, {"auto", "exhaustive", "sequential"},
                 "auto: exhaustive up to exhaustive_max_images photos, else sequential (video)");
  set.add("exhaustive_max_images", o.exhaustive_max_images,
          "largest photo count matched exhaustively by matcher=auto", 2, 100000);
  set.add("sequential_overlap", o.sequential_overlap, "neighbours matched per frame (sequential)", 1,
          1000);
  set.add("max_image_size", o.max_image_size,
          "downscale photos whose longest side exceeds this (pixels); 0 = keep", 0, 100000);
  set.add("min_image_size", o.min_image_size, "skip photos whose shorter side is smaller (pixels)", 1,
          100000);
  set.add("max_num_features", o.max_num_features, "SIFT features per photo", 100, 1000000);
  set.add("sift_peak_threshold", o.sift_peak_threshold,
          "SIFT contrast threshold (COLMAP default 0.0067; lower = more features)", 0.0005, 0.1);
  set.add("num_threads", o.num_threads, "COLMAP threads; -1 = all cores", -1, 1024);
  set.add_choice("use_gpu", o.use_gpu, {"auto", "yes", "no"},
                 "auto: GPU SIFT only if COLMAP was built with CUDA");
  set.add("min_pose_inliers", o.min_pose_inliers,
          "inlier matches the mapper needs to register a photo (COLMAP default 30)", 6, 10000);
  set.add("min_registered_images", o.min_registered_images,
          "fewer registered photos fail the stage", 3, 1000000);
  set.add("random_seed", o.random_seed, "COLMAP random seed (repeatable runs)", 0, 2147483647);
}

}  // namespace hos::sfm
