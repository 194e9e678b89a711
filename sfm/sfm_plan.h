// What the sfm stage asks of COLMAP for one photo set: the matching strategy
// and the feature, match and image-size budgets that fit the photo count and
// size. A pure function of the photos' facts and the options, so the choices
// are testable without COLMAP.
#pragma once

#include <string>

#include "sfm/sfm_options.h"

namespace hos::sfm {

// What the stage knows about the staged photos before COLMAP runs.
struct PhotoSetFacts {
  int photos = 0;
  int photos_with_gps = 0;  // EXIF GPS latitude and longitude present
  int longest_side_px = 0;  // of the largest staged photo
};

struct SfmPlan {
  // "exhaustive", "vocab_tree", "sequential" or "spatial".
  std::string matcher;
  // Why: "11 photos <= sfm.exhaustive_max_images (60)", "sfm.matcher", ...
  std::string matcher_reason;
  int max_num_features = 0;     // SIFT features per photo
  int max_num_matches = 0;      // verified matches kept per pair
  int sift_max_image_size = 0;  // longest side SIFT sees (pixels)
  bool sift_upsample = false;   // also search at 2x size (COLMAP first_octave -1)
  int vocab_tree_words = 0;     // visual words of the tree (vocab_tree only)
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

}  // namespace hos::sfm
