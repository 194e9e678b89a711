// Options of the sfm stage (YAML section "sfm").
#pragma once

#include <string>

#include "core/option_set.h"

namespace hos::sfm {

struct SfmOptions {
  // COLMAP executable (a name looked up on PATH, or a path). $HOS_COLMAP
  // replaces the default "colmap".
  std::string colmap = "colmap";
  // COLMAP camera model for feature extraction (undistortion makes it PINHOLE).
  std::string camera_model = "SIMPLE_RADIAL";
  // "auto": one shared camera when all photos have the same size and EXIF
  // focal length; "single": always one; "per_image": one camera per photo.
  std::string camera_mode = "auto";
  // "auto": exhaustive up to exhaustive_max_images photos, else sequential.
  std::string matcher = "auto";
  int exhaustive_max_images = 200;
  int sequential_overlap = 10;  // neighbours matched per frame by the sequential matcher
  // Photos larger than this (longest side, pixels) are downscaled into the
  // workspace before COLMAP sees them; 0 keeps the original size.
  int max_image_size = 0;
  int min_image_size = 64;      // photos with a shorter side are skipped
  int max_num_features = 8192;  // SIFT features per photo
  // SIFT contrast threshold. Below COLMAP's 0.0067 so that small photos and
  // sparsely textured objects get enough features; large photos reach
  // max_num_features either way.
  double sift_peak_threshold = 0.003;
  int num_threads = -1;         // COLMAP threads; -1 = all cores
  // "auto" uses the GPU only if the COLMAP binary reports CUDA support.
  std::string use_gpu = "auto";
  // Inliers the mapper needs to register a photo. COLMAP's default (30) drops
  // views of small, sparsely textured objects that match their neighbours
  // with only 15-30 features; 15 still rejects chance matches.
  int min_pose_inliers = 15;
  int min_registered_images = 3;  // fewer registered photos is a failure
  int random_seed = 0;            // COLMAP's random seed, for repeatable runs

  // Throws ConfigError naming the key and the allowed values.
  void validate() const;
};

void register_options(OptionSet& set, SfmOptions& options);

}  // namespace hos::sfm
