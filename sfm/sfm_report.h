// The sfm stage's report (WS/sfm/report.json, written last) for the run
// report and the later stages: photos registered and why not, skipped
// files, the photos' GPS, video clips, masks, the sparse model's figures,
// the principal point, COLMAP's models, the matching plan and step times.
// Its JSON keys are in sfm_report.cpp alone: the stage writes and the
// pipeline reads it through these functions.
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sfm/sfm.h"

namespace hos::sfm {

// One video clip among the photos: its frames read, kept and dropped by reason.
struct VideoClipReport {
  std::string file;
  std::string name;  // staged name of the clip
  int frames = 0;
  double fps = 0.0;
  std::vector<int> kept_frames;  // indices
  int dropped_too_little_motion = 0;
  int dropped_blurred = 0;
  int dropped_over_max_frames = 0;
};

// One feature extraction run of the plan (sfm/sfm_plan.h ExtractionRun).
struct ExtractionReport {
  int photos = 0;
  std::string description;
  bool single_camera = false;
  int sift_max_image_size = 0;
  bool sift_upsample = false;
};

// What COLMAP was asked to do (sfm/sfm_plan.h SfmPlan).
struct SfmPlanReport {
  std::string matcher;
  std::string matcher_reason;
  bool spatial_ignore_z = false;
  int max_num_features = 0;
  int max_num_matches = 0;
  int vocab_tree_words = 0;
  std::vector<ExtractionReport> extractions;
};

// The fields are SfmResult's (sfm/sfm.h), as the file has them.
struct SfmReport {
  int images_given = 0;
  int images_registered = 0;
  double registered_fraction = 0.0;
  std::string warning;  // the coverage warning; empty when none (left out of the file)
  std::vector<std::string> unregistered;
  std::vector<UnregisteredPhoto> unregistered_photos;
  std::vector<SkippedInput> skipped;
  std::vector<PhotoGps> photos;         // every usable photo, with its GPS if it has one
  std::vector<VideoClipReport> videos;  // left out of the file when empty
  int masked_photos = 0;
  int masks_undistorted = 0;
  std::int64_t points = 0;
  double mean_reprojection_error_px = 0.0;
  double mean_track_length = 0.0;
  bool principal_point_estimated = false;
  double principal_point_offset_px = 0.0;
  std::vector<CameraPrincipalPoint> principal_points;
  std::vector<SfmModelSummary> models;
  int used_model = 0;
  std::string matcher;
  std::optional<SfmPlanReport> plan;  // none for an existing model
  int cameras_planned = 0;
  int position_priors = -1;  // -1: not checked (left out of the file)
  std::string colmap_version;
  std::vector<std::pair<std::string, double>> step_seconds;  // in the order the steps ran
  double total_seconds = 0.0;
};

// The report of a run.
SfmReport sfm_report(const SfmResult& result);

nlohmann::ordered_json to_json(const SfmReport& report);
// Throws InputError naming the file when it is missing or malformed.
SfmReport read_sfm_report(const std::filesystem::path& path);

// Writes sfm_report(result) atomically; throws OutputError.
void write_sfm_report(const SfmResult& result, const std::filesystem::path& file);

}  // namespace hos::sfm
