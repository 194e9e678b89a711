// Options of the sfm stage (YAML section "sfm").
#pragma once

#include <filesystem>
#include <string>

#include "core/option_set.h"

namespace hos::sfm {

struct SfmOptions {
  // COLMAP executable (a name looked up on PATH, or a path). $HOS_COLMAP
  // replaces the default "colmap".
  std::string colmap = "colmap";
  // COLMAP camera model for feature extraction (undistortion makes it PINHOLE).
  std::string camera_model = "SIMPLE_RADIAL";
  // "auto": one camera per group of photos with the same size, EXIF focal
  // length, make and model (sfm_plan.h, camera_groups); "single": one camera
  // per photo size, EXIF ignored; "per_image": one camera per photo.
  std::string camera_mode = "auto";
  // How photo pairs are chosen for matching (sfm/sfm_plan.h):
  // "auto": exhaustive up to exhaustive_max_images photos; above that spatial
  // when most photos carry GPS EXIF, else a vocabulary tree built from the
  // photos' own features. "sequential" suits ordered video frames.
  std::string matcher = "auto";
  // Exhaustive matching costs (n-1)/2 pairs a photo, the tree at most
  // vocab_tree_neighbors plus its build: on 36 photos, with 10 neighbours, the
  // tree matched 251 of the 630 pairs in half the CPU time.
  int exhaustive_max_images = 30;
  int sequential_overlap = 10;  // neighbours matched per frame by the sequential matcher
  // Video clips among the photos (sfm/video_frames.h): at most
  // video_max_frames frames a clip (evenly thinned when more qualify); a
  // frame is kept once the median tracked feature has moved video_min_motion
  // of the longer image side since the last kept frame, unless its sharpness
  // (variance of the Laplacian) is below video_blur_ratio of the median of
  // its neighbours' (motion blur; 0 keeps blurred frames).
  int video_max_frames = 120;
  double video_min_motion = 0.05;
  double video_blur_ratio = 0.6;
  // Vocabulary tree matching: photos retrieved (and matched) per photo, and
  // the tree's visual words (0 = auto: sfm_plan.h, vocab_tree_words_for).
  int vocab_tree_neighbors = 12;
  int vocab_tree_words = 0;
  int spatial_neighbors = 20;  // nearest photos by GPS position matched per photo
  // Photos larger than this (longest side, pixels) are downscaled into the
  // workspace before COLMAP sees them (so the undistorted images for mvs and
  // texture shrink too); 0 keeps the original size.
  int max_image_size = 0;
  // Longest side SIFT works at (COLMAP's SiftExtraction.max_image_size):
  // keypoints come back in full-size coordinates and the undistorted images
  // keep the full size; 0 = no bound.
  int sift_max_image_size = 2400;
  // Photos whose SIFT size is below this (longest side, pixels) are also
  // searched at twice their size (COLMAP first_octave -1): small photos need
  // those fine features, large ones have plenty without, at a quarter of the
  // work. 0 = never upsample.
  int sift_upsample_below = 1200;
  int min_image_size = 64;  // photos with a shorter side are skipped
  // SIFT features per photo; 0 = auto (sfm_plan.h: 4096 for up to 20
  // photos, falling as 1/sqrt(count) to 2048 from 80 photos on).
  int max_num_features = 0;
  // Verified matches kept per photo pair; 0 = auto (half the features).
  int max_num_matches = 0;
  // SIFT contrast threshold. Below COLMAP's 0.0067 so that small photos and
  // sparsely textured objects get enough features; large photos reach
  // max_num_features either way.
  double sift_peak_threshold = 0.003;
  int num_threads = -1;  // COLMAP threads; -1 = all cores
  // "auto" uses the GPU only if the COLMAP binary reports CUDA support.
  std::string use_gpu = "auto";
  // Inliers the mapper needs to register a photo. COLMAP's default (30) drops
  // views of small, sparsely textured objects that match their neighbours
  // with only 15-30 features; 15 still rejects chance matches.
  int min_pose_inliers = 15;
  // Global bundle adjustment runs when the model grew by this factor since
  // the last one (COLMAP Mapper.ba_global_images_ratio / points_ratio, default
  // 1.1); the final global adjustment always runs.
  double ba_global_ratio = 1.1;
  // After mapping, a bundle adjustment that also estimates the principal
  // point, which COLMAP's mapper keeps at the image centre. A shifted or
  // cropped sensor puts it pixels away, which the mapper absorbs into the
  // focal length and distortion; finer matching levels then miss by pixels.
  // An estimate farther than this fraction of the longer side from the
  // centre is taken as unconstrained by the photos and discarded. 0 = keep
  // the centre.
  double principal_point_max_offset = 0.1;
  // The principal point of a camera is estimated only when at least this
  // many registered photos share it: one or two photos cannot tell a shifted
  // centre from a turned camera (a per-photo estimate was 38.8 px off
  // centre with a 3.9 degree rotation error). Other cameras keep the centre.
  int principal_point_min_images = 5;
  // A warning (terminal, report.json, run report) when fewer than this
  // fraction of the usable photos registered.
  double registered_warning_fraction = 0.9;
  int min_registered_images = 3;  // fewer registered photos is a failure
  int random_seed = 0;            // COLMAP's random seed, for repeatable runs
  // Folder of masks (sfm/photo_masks.h): the mask of photo NAME (its path
  // relative to the photo folder) is NAME.png there, black = masked out.
  // "none": a PNG named NAME.png beside photo NAME is its mask.
  std::string masks = "none";
  // The folder of masks; empty for "none".
  std::filesystem::path mask_folder() const;

  // Throws ConfigError naming the key and the allowed values.
  void validate() const;
};

void register_options(OptionSet& set, SfmOptions& options);

}  // namespace hos::sfm
