// What the sfm stage asks of COLMAP for one photo set: the cameras (groups
// of photos that share one), the feature extraction runs with their SIFT
// sizes, the matching strategy and the feature, match and image-size
// budgets. Pure functions of the photos' facts and the options, so the
// choices are testable without COLMAP.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sfm/image_inputs.h"
#include "sfm/sfm_options.h"

namespace hos::sfm {

// Photos one COLMAP camera fits: the same staged size and, with
// camera_mode auto, the same EXIF focal length, make and model.
struct CameraGroup {
  int width = 0;
  int height = 0;
  std::optional<double> focal_length_mm;
  std::string camera_make;
  std::string camera_model;
  std::string video_clip;          // the clip whose frames these are; empty for photos
  std::vector<std::string> names;  // staged names, sorted

  int longest_side_px() const { return width > height ? width : height; }
  // "12 photos 400x300, 4.2 mm, Apple iPhone 12".
  std::string describe() const;
};

// The groups of images (in the order of their first photo's name).
// camera_mode auto and per_image group by size, EXIF focal length, make,
// model and video clip (each clip its own camera); single by size only (one
// COLMAP camera cannot span two sizes).
std::vector<CameraGroup> camera_groups(const std::vector<StagedImage>& images, const std::string& camera_mode);

// What the stage knows about the staged photos before COLMAP runs.
struct PhotoSetFacts {
  int photos = 0;
  int photos_with_gps = 0;          // EXIF GPS latitude and longitude present
  int photos_without_altitude = 0;  // of those, without an EXIF altitude
  std::vector<CameraGroup> groups;  // camera_groups of the photos
  int video_frames = 0;             // of the photos, frames of video clips
};
PhotoSetFacts photo_set_facts(const std::vector<StagedImage>& images, const std::string& camera_mode);

// One run of COLMAP's feature_extractor over some of the photos (its image
// list), with the SIFT size that suits their size: a large photo never
// turns off the upsampled octave of small ones.
struct ExtractionRun {
  std::vector<std::string> names;  // staged names
  int longest_side_px = 0;         // of its largest photo
  int sift_max_image_size = 0;     // longest side SIFT sees (pixels)
  bool sift_upsample = false;      // also search at 2x size (COLMAP first_octave -1)
  bool single_camera = false;      // one shared COLMAP camera for the run's photos
  std::string description;         // the group(s), for the log
};

struct SfmPlan {
  // "exhaustive", "vocab_tree", "sequential" or "spatial".
  std::string matcher;
  // Why: "11 photos <= sfm.exhaustive_max_images (60)", "sfm.matcher", ...
  std::string matcher_reason;
  // Spatial matching by latitude and longitude only: some photos carry no
  // EXIF altitude (their staged copies hold altitude 0).
  bool spatial_ignore_z = false;
  // Sequential matching also retrieves loop closures with a vocabulary
  // tree learnt from the photos (vocab_tree_words words).
  bool loop_detection = false;
  int max_num_features = 0;  // SIFT features per photo
  int max_num_matches = 0;   // verified matches kept per pair
  int vocab_tree_words = 0;  // visual words of the tree (vocab_tree, or loop_detection)
  // One per camera group with several photos; groups of one photo (and
  // every group with camera_mode per_image) that share a SIFT plan share a
  // run with one camera per photo.
  std::vector<ExtractionRun> extractions;
};

// Features per photo for matcher=auto sets of `photos` photos: 4096 up to 20
// photos, then 4096 * sqrt(20 / photos) (so exhaustive matching work, pairs x
// features^2, grows linearly rather than quadratically with the count) in steps
// of 256, never below 2048.
int features_for_photo_count(int photos);

// Visual words for a tree built from `features` descriptors of `photos`
// photos: about 100 descriptors per word (k-means needs several per cluster),
// at least 256. Up to 300 photos at most 768: from about 1000 words on,
// COLMAP autotunes the search index of the words, 30-45 s whatever the set
// (36 photos: 768 words built in 5 CPU s, 1021 words in 31). With 768 words
// every photo of a 100-photo set registered at the accuracy of exhaustive
// matching (docs/benchmarks-sfm.md).
int vocab_tree_words_for(int photos, long long features);

// The choices for these photos; explicit options win over "auto" (0).
SfmPlan plan_sfm(const PhotoSetFacts& facts, const SfmOptions& options);

// After feature extraction: spatial matching with fewer position priors in
// COLMAP's database than photos would match the photos without one as if
// they stood at the origin. Then exhaustive (up to exhaustive_max_images
// photos) or vocabulary tree matching instead, with the reason. Returns
// whether the plan changed.
bool fall_back_from_spatial(SfmPlan& plan,
                            const PhotoSetFacts& facts,
                            int photos_with_priors,
                            const SfmOptions& options);

}  // namespace hos::sfm
