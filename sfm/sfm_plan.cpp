#include "sfm/sfm_plan.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/reporter.h"

namespace hos::sfm {
namespace {

constexpr int kMostFeatures = 4096;    // small sets: each pair matters
constexpr int kFewestFeatures = 2048;  // still registers 800x600 views robustly
constexpr int kFullFeatureCount = 20;  // photos up to which kMostFeatures apply
constexpr int kFeatureStep = 256;
constexpr long long kFeaturesPerWord = 100;
constexpr int kFewestWords = 256;
constexpr int kWordsBelowIndexTuning = 768;  // see vocab_tree_words_for
constexpr int kSmallTreePhotos = 300;

std::string choose_matcher(const PhotoSetFacts& facts, const SfmOptions& options, std::string& reason) {
  if (options.matcher != "auto") {
    reason = "sfm.matcher";
    return options.matcher;
  }
  if (facts.photos <= options.exhaustive_max_images) {
    reason = format_message(facts.photos, " photos <= sfm.exhaustive_max_images (", options.exhaustive_max_images, ")");
    return "exhaustive";
  }
  // Spatial matching needs a position for every photo: one without would be
  // matched as if it stood at the origin.
  if (facts.photos_with_gps == facts.photos) {
    reason = format_message(facts.photos, " photos, all with GPS EXIF");
    return "spatial";
  }
  reason = format_message(facts.photos, " photos > sfm.exhaustive_max_images (", options.exhaustive_max_images, "), ",
                          facts.photos_with_gps == 0 ? std::string("no") : std::string("not all with"), " GPS EXIF");
  return "vocab_tree";
}

}  // namespace

int features_for_photo_count(int photos) {
  if (photos <= kFullFeatureCount) return kMostFeatures;
  const double scaled = kMostFeatures * std::sqrt(double(kFullFeatureCount) / photos);
  const int stepped = static_cast<int>(std::lround(scaled / kFeatureStep)) * kFeatureStep;
  return std::max(kFewestFeatures, stepped);
}

int vocab_tree_words_for(int photos, long long features) {
  const long long words = std::max<long long>(kFewestWords, features / kFeaturesPerWord);
  return static_cast<int>(photos <= kSmallTreePhotos ? std::min<long long>(words, kWordsBelowIndexTuning) : words);
}

SfmPlan plan_sfm(const PhotoSetFacts& facts, const SfmOptions& options) {
  SfmPlan plan;
  plan.matcher = choose_matcher(facts, options, plan.matcher_reason);
  plan.max_num_features =
      options.max_num_features > 0 ? options.max_num_features : features_for_photo_count(facts.photos);
  plan.max_num_matches = options.max_num_matches > 0 ? options.max_num_matches : plan.max_num_features / 2;
  // COLMAP needs a number; the largest photo's side means "no bound".
  plan.sift_max_image_size =
      options.sift_max_image_size > 0 ? options.sift_max_image_size : std::max(facts.longest_side_px, 1);
  const int sift_side = std::min(plan.sift_max_image_size, facts.longest_side_px);
  plan.sift_upsample = options.sift_upsample_below > 0 && sift_side < options.sift_upsample_below;
  if (plan.matcher == "vocab_tree") {
    plan.vocab_tree_words =
        options.vocab_tree_words > 0
            ? options.vocab_tree_words
            : vocab_tree_words_for(facts.photos, static_cast<long long>(facts.photos) * plan.max_num_features);
  }
  return plan;
}

}  // namespace hos::sfm
