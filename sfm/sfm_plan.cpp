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

// Exhaustive up to the limit, else a tree learnt from the photos.
std::string matcher_without_positions(const PhotoSetFacts& facts, const SfmOptions& options, std::string& reason) {
  if (facts.photos <= options.exhaustive_max_images) {
    reason = format_message(facts.photos, " photos <= sfm.exhaustive_max_images (", options.exhaustive_max_images, ")");
    return "exhaustive";
  }
  reason = format_message(facts.photos, " photos > sfm.exhaustive_max_images (", options.exhaustive_max_images, ")");
  return "vocab_tree";
}

std::string altitude_note(const PhotoSetFacts& facts) {
  if (facts.photos_without_altitude == 0) return "";
  return format_message("; ", facts.photos_without_altitude,
                        " without altitude: matched by latitude and longitude only");
}

std::string choose_matcher(const PhotoSetFacts& facts, const SfmOptions& options, std::string& reason) {
  if (options.matcher != "auto") {
    reason = "sfm.matcher";
    if (options.matcher == "spatial") reason += altitude_note(facts);
    return options.matcher;
  }
  if (facts.photos <= options.exhaustive_max_images) return matcher_without_positions(facts, options, reason);
  // Video frames are ordered: each overlaps its neighbours in the clip.
  if (facts.video_frames == facts.photos) {
    reason =
        format_message(facts.photos, " video frames > sfm.exhaustive_max_images (", options.exhaustive_max_images, ")");
    return "sequential";
  }
  // Spatial matching needs a position for every photo: one without would be
  // matched as if it stood at the origin.
  if (facts.photos_with_gps == facts.photos) {
    reason = format_message(facts.photos, " photos, all with GPS EXIF", altitude_note(facts));
    return "spatial";
  }
  std::string matcher = matcher_without_positions(facts, options, reason);
  reason += facts.photos_with_gps == 0 ? ", no GPS EXIF" : ", not all with GPS EXIF";
  return matcher;
}

bool same_camera(const CameraGroup& group, const StagedImage& image, bool size_only) {
  if (group.width != image.width || group.height != image.height) return false;
  return size_only || (group.focal_length_mm == image.focal_length_mm && group.camera_make == image.camera_make &&
                       group.camera_model == image.camera_model && group.video_clip == image.video_clip);
}

ExtractionRun run_of(const CameraGroup& group, bool single_camera, const SfmOptions& options) {
  ExtractionRun run;
  run.names = group.names;
  run.longest_side_px = group.longest_side_px();
  // COLMAP needs a number; the largest photo's side means "no bound".
  run.sift_max_image_size =
      options.sift_max_image_size > 0 ? options.sift_max_image_size : std::max(run.longest_side_px, 1);
  const int sift_side = std::min(run.sift_max_image_size, run.longest_side_px);
  run.sift_upsample = options.sift_upsample_below > 0 && sift_side < options.sift_upsample_below;
  run.single_camera = single_camera;
  run.description = group.describe();
  return run;
}

// Runs with one camera per photo and the same SIFT plan are one run.
void add_merged(std::vector<ExtractionRun>& runs, ExtractionRun run) {
  for (ExtractionRun& other : runs) {
    // With a SIFT bound every run has it; without one the larger side
    // still bounds nothing.
    if (other.single_camera || other.sift_upsample != run.sift_upsample) continue;
    other.names.insert(other.names.end(), run.names.begin(), run.names.end());
    other.longest_side_px = std::max(other.longest_side_px, run.longest_side_px);
    other.sift_max_image_size = std::max(other.sift_max_image_size, run.sift_max_image_size);
    other.description = format_message(other.names.size(), " photos of several sizes or cameras");
    return;
  }
  runs.push_back(std::move(run));
}

std::vector<ExtractionRun> plan_extractions(const PhotoSetFacts& facts, const SfmOptions& options) {
  std::vector<ExtractionRun> runs;
  for (const CameraGroup& group : facts.groups) {
    const bool shared = options.camera_mode != "per_image" && group.names.size() > 1;
    ExtractionRun run = run_of(group, shared, options);
    if (shared) {
      runs.push_back(std::move(run));
    } else {
      add_merged(runs, std::move(run));
    }
  }
  for (ExtractionRun& run : runs) std::sort(run.names.begin(), run.names.end());
  return runs;
}

}  // namespace

std::string CameraGroup::describe() const {
  std::string text = format_message(names.size(), names.size() == 1 ? " photo " : " photos ", width, "x", height);
  if (focal_length_mm) text += format_message(", ", *focal_length_mm, " mm");
  const std::string camera =
      camera_make.empty() || camera_model.empty() ? camera_make + camera_model : camera_make + " " + camera_model;
  if (!camera.empty()) text += ", " + camera;
  if (!video_clip.empty()) text += ", frames of " + video_clip;
  return text;
}

std::vector<CameraGroup> camera_groups(const std::vector<StagedImage>& images, const std::string& camera_mode) {
  std::vector<StagedImage> sorted = images;
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  const bool size_only = camera_mode == "single";
  std::vector<CameraGroup> groups;
  for (const StagedImage& image : sorted) {
    auto group = std::find_if(groups.begin(), groups.end(),
                              [&](const CameraGroup& g) { return same_camera(g, image, size_only); });
    if (group == groups.end()) {
      CameraGroup created;
      created.width = image.width;
      created.height = image.height;
      if (!size_only) {
        created.focal_length_mm = image.focal_length_mm;
        created.camera_make = image.camera_make;
        created.camera_model = image.camera_model;
        created.video_clip = image.video_clip;
      }
      groups.push_back(created);
      group = groups.end() - 1;
    }
    group->names.push_back(image.name);
  }
  return groups;
}

PhotoSetFacts photo_set_facts(const std::vector<StagedImage>& images, const std::string& camera_mode) {
  PhotoSetFacts facts;
  facts.photos = static_cast<int>(images.size());
  for (const StagedImage& image : images) {
    facts.photos_with_gps += image.gps ? 1 : 0;
    facts.photos_without_altitude += image.gps && !image.gps->altitude_m ? 1 : 0;
    facts.video_frames += image.video_clip.empty() ? 0 : 1;
  }
  facts.groups = camera_groups(images, camera_mode);
  return facts;
}

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

namespace {

// Sequential matching already pairs every frame with its overlap
// neighbours; loops need a set several times longer than that.
bool wants_loop_detection(const SfmPlan& plan, const PhotoSetFacts& facts, const SfmOptions& options) {
  return plan.matcher == "sequential" && facts.photos > 2 * (options.sequential_overlap + 1);
}

void set_vocab_tree_words(SfmPlan& plan, const PhotoSetFacts& facts, const SfmOptions& options) {
  plan.vocab_tree_words = 0;
  if (plan.matcher != "vocab_tree" && !plan.loop_detection) return;
  plan.vocab_tree_words =
      options.vocab_tree_words > 0
          ? options.vocab_tree_words
          : vocab_tree_words_for(facts.photos, static_cast<long long>(facts.photos) * plan.max_num_features);
}

}  // namespace

SfmPlan plan_sfm(const PhotoSetFacts& facts, const SfmOptions& options) {
  SfmPlan plan;
  plan.matcher = choose_matcher(facts, options, plan.matcher_reason);
  plan.spatial_ignore_z = plan.matcher == "spatial" && facts.photos_without_altitude > 0;
  plan.max_num_features =
      options.max_num_features > 0 ? options.max_num_features : features_for_photo_count(facts.photos);
  plan.max_num_matches = options.max_num_matches > 0 ? options.max_num_matches : plan.max_num_features / 2;
  plan.loop_detection = wants_loop_detection(plan, facts, options);
  if (plan.loop_detection) plan.matcher_reason += ", loop closures by a vocabulary tree";
  set_vocab_tree_words(plan, facts, options);
  plan.extractions = plan_extractions(facts, options);
  return plan;
}

bool fall_back_from_spatial(SfmPlan& plan,
                            const PhotoSetFacts& facts,
                            int photos_with_priors,
                            const SfmOptions& options) {
  if (plan.matcher != "spatial" || photos_with_priors >= facts.photos) return false;
  std::string reason;
  plan.matcher = matcher_without_positions(facts, options, reason);
  plan.matcher_reason = format_message(reason, "; not spatial: only ", photos_with_priors, " of ", facts.photos,
                                       " photos have a position prior in COLMAP's database");
  plan.spatial_ignore_z = false;
  set_vocab_tree_words(plan, facts, options);
  return true;
}

}  // namespace hos::sfm
