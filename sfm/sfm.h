// The sfm stage: photos in, registered cameras and undistorted images out,
// by running COLMAP (feature extraction, matching, mapping, undistortion).
//
// Workspace layout (under the stage's workspace root WS):
//   WS/sfm/images/           the usable photos (links, or upright/downscaled copies)
//   WS/sfm/database.db       COLMAP's feature and match database
//   WS/sfm/vocab_tree.bin    vocabulary tree learnt from the photos (vocab_tree matcher)
//   WS/sfm/sparse/<k>/       COLMAP's models (several if the photos split)
//   WS/sfm/undistorted/      the result: images/ + sparse/ (PINHOLE), see
//                            core/undistorted_workspace.h; written atomically
//   WS/sfm/report.json       figures of the run (written last)
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/reporter.h"
#include "core/sparse_model.h"
#include "sfm/image_inputs.h"
#include "sfm/sfm_options.h"
#include "sfm/sfm_plan.h"

namespace hos::sfm {

struct SfmPaths {
  std::filesystem::path root;  // WS/sfm
  std::filesystem::path images;
  std::filesystem::path thumbnails;  // NAME.jpg per usable photo, for the run report
  std::filesystem::path database;
  std::filesystem::path vocab_tree;
  std::filesystem::path sparse;
  std::filesystem::path undistorted;
  std::filesystem::path report;
};
SfmPaths sfm_paths(const std::filesystem::path& workspace);

struct SfmInput {
  std::filesystem::path images;     // the user's photo folder
  std::filesystem::path workspace;  // WS
  // Optional: an existing COLMAP sparse model of these images. SfM is then
  // skipped and only undistortion runs (nothing at all if the cameras are
  // already distortion-free pinholes).
  std::filesystem::path existing_model;
};

struct SfmModelSummary {
  int index = 0;  // folder name under WS/sfm/sparse
  int images = 0;
  std::int64_t points = 0;
};

struct SfmResult {
  std::filesystem::path undistorted;  // the undistorted workspace
  int images_given = 0;
  int images_registered = 0;
  std::vector<std::string> unregistered;  // names of usable photos COLMAP did not register
  std::vector<SkippedInput> skipped;      // files of the folder that were not usable
  std::int64_t points = 0;
  double mean_reprojection_error_px = 0.0;
  double mean_track_length = 0.0;
  // The principal point after the final adjustment (options'
  // principal_point_max_offset): its largest distance from the image centre
  // over the cameras (pixels; 0 when not estimated), and whether the estimate
  // was kept (else the centre was).
  double principal_point_offset_px = 0.0;
  bool principal_point_estimated = false;
  std::vector<SfmModelSummary> models;  // every model COLMAP produced
  int used_model = 0;
  std::string matcher;  // plan.matcher, or "existing model"
  SfmPlan plan;         // what COLMAP was asked to do (empty for an existing model)
  bool single_camera = false;
  std::string colmap_version;
  // Step -> wall time: "prepare_images", then each COLMAP command.
  std::vector<std::pair<std::string, double>> step_seconds;
  double total_seconds = 0.0;  // the whole stage
};

// The largest distance of a camera's principal point from its image centre
// over the model's cameras, in pixels and as a fraction of that camera's
// longer side.
struct PrincipalPointOffset {
  double pixels = 0.0;
  double fraction = 0.0;
};
PrincipalPointOffset largest_principal_point_offset(const SparseModel& model);

// Runs the stage. Throws InputError (bad photo folder or model), StageError
// (COLMAP missing or failed, too few images registered), Cancelled.
SfmResult run_sfm(const SfmInput& input, const SfmOptions& options, Reporter& reporter);

// The figures as JSON (WS/sfm/report.json), written atomically.
void write_sfm_report(const SfmResult& result, const std::filesystem::path& file);

// "times: total 41.2 s; prepare_images 0.3 s; feature_extractor 12.0 s; ...".
std::string step_times_text(const SfmResult& result);

// A few lines for the terminal: registered/given, points, errors, the
// matching plan, per-step times.
std::vector<std::string> sfm_summary_lines(const SfmResult& result);

}  // namespace hos::sfm
