#include "sfm/sfm_options.h"

#include "core/error.h"
#include "core/option_set.h"

namespace hos::sfm {
namespace {

constexpr int kMinFeatures = 100;  // fewer cannot register a photo reliably

}  // namespace

void SfmOptions::validate() const {
  check_option_table("sfm", *this);
  if (sift_max_image_size != 0 && sift_max_image_size < min_image_size) {
    throw ConfigError("sfm.sift_max_image_size", "value " + std::to_string(sift_max_image_size) +
                                                     " must be 0 (no bound) or at least sfm.min_image_size (" +
                                                     std::to_string(min_image_size) + ")");
  }
  if (max_image_size != 0 && max_image_size < min_image_size) {
    throw ConfigError("sfm.max_image_size", "value " + std::to_string(max_image_size) +
                                                " must be 0 (off) or at least sfm.min_image_size (" +
                                                std::to_string(min_image_size) + ")");
  }
}

std::filesystem::path SfmOptions::mask_folder() const {
  return masks == "none" ? std::filesystem::path() : std::filesystem::path(masks);
}

void register_options(OptionSet& set, SfmOptions& o) {
  set.add("colmap", o.colmap, "COLMAP executable (name on PATH or path); $HOS_COLMAP replaces the default");
  set.add_choice("camera_model", o.camera_model, {"SIMPLE_PINHOLE", "PINHOLE", "SIMPLE_RADIAL", "RADIAL", "OPENCV"},
                 "COLMAP camera model estimated by the mapper");
  set.add_choice("camera_mode", o.camera_mode, {"auto", "single", "per_image"},
                 "auto: one camera per group of photos sharing size, EXIF focal length, make and model; "
                 "single: one per photo size; per_image: one per photo");
  set.add_choice("matcher", o.matcher, {"auto", "exhaustive", "vocab_tree", "sequential", "spatial"},
                 "auto: exhaustive up to exhaustive_max_images photos, then spatial (GPS EXIF) or a "
                 "vocabulary tree built from the photos; sequential for video frames");
  set.add("exhaustive_max_images", o.exhaustive_max_images, "largest photo count matched exhaustively by matcher=auto",
          2, 100000);
  set.add("sequential_overlap", o.sequential_overlap, "neighbours matched per frame (sequential)", 1, 1000);
  set.add("video_max_frames", o.video_max_frames, "frames kept per video clip at most (evenly thinned beyond)", 3,
          100000);
  set.add("video_min_motion", o.video_min_motion,
          "a video frame is kept once tracked features moved this fraction of the longer side (median) since the "
          "last kept frame",
          0.001, 1.0);
  set.add("video_blur_ratio", o.video_blur_ratio,
          "video frames sharper than this fraction of their neighbours' median sharpness only; 0 = keep blurred", 0.0,
          1.0);
  set.add("vocab_tree_neighbors", o.vocab_tree_neighbors, "photos retrieved and matched per photo (vocab_tree)", 2,
          10000);
  set.add("vocab_tree_words", o.vocab_tree_words,
          "visual words of the tree built from the photos; 0 = auto (about 100 features a word, at most 768 "
          "up to 300 photos)",
          0, 1000000);
  set.add("spatial_neighbors", o.spatial_neighbors, "nearest photos by GPS matched per photo (spatial)", 2, 10000);
  set.add("max_image_size", o.max_image_size,
          "downscale photos (and the undistorted images) whose longest side exceeds this (pixels); "
          "0 = keep",
          0, 100000);
  set.add("sift_max_image_size", o.sift_max_image_size,
          "longest side SIFT works at (pixels); undistorted images stay full size; 0 = no bound", 0, 100000);
  set.add("sift_upsample_below", o.sift_upsample_below,
          "SIFT also at 2x size for photos whose SIFT size is below this (pixels); 0 = never", 0, 100000);
  set.add("min_image_size", o.min_image_size, "skip photos whose shorter side is smaller (pixels)", 1, 100000);
  set.add_zero_or("max_num_features", o.max_num_features,
                  "SIFT features per photo; 0 = auto (4096 up to 20 photos, down to 2048 from 80)", kMinFeatures,
                  1000000);
  set.add("max_num_matches", o.max_num_matches, "matches kept per photo pair; 0 = auto (half the features)", 0,
          1000000);
  set.add("sift_peak_threshold", o.sift_peak_threshold,
          "SIFT contrast threshold (COLMAP default 0.0067; lower = more features)", 0.0005, 0.1);
  set.add("num_threads", o.num_threads, "COLMAP threads; -1 = all cores", -1, 1024);
  set.add_choice("use_gpu", o.use_gpu, {"auto", "yes", "no"}, "auto: GPU SIFT only if COLMAP was built with CUDA");
  set.add("min_pose_inliers", o.min_pose_inliers,
          "inlier matches the mapper needs to register a photo (COLMAP default 30)", 6, 10000);
  set.add("ba_global_ratio", o.ba_global_ratio,
          "global bundle adjustment when the model grew by this factor (COLMAP default 1.1)", 1.01, 10.0);
  set.add("principal_point_max_offset", o.principal_point_max_offset,
          "after mapping, estimate the principal point (COLMAP keeps the image centre); an estimate farther "
          "than this fraction of the longer side from the centre is discarded; 0 = keep the centre",
          0.0, 0.5);
  set.add("principal_point_min_images", o.principal_point_min_images,
          "estimate the principal point only of cameras shared by at least this many registered photos", 2, 1000000);
  set.add("registered_warning_fraction", o.registered_warning_fraction,
          "warn when fewer than this fraction of the usable photos registered", 0.0, 1.0);
  set.add("min_registered_images", o.min_registered_images, "fewer registered photos fail the stage", 3, 1000000);
  set.add("random_seed", o.random_seed, "COLMAP random seed (repeatable runs)", 0, 2147483647);
  set.add("masks", o.masks,
          "folder of masks: PHOTO.png for photo PHOTO (its path under the photo folder), black = not used; "
          "none: PHOTO.png beside PHOTO");
  set.add_flag("--masks", "masks");
}

}  // namespace hos::sfm
