// The sfm stage: photos in, registered cameras and undistorted images out,
// by running COLMAP (feature extraction, matching, mapping, undistortion).
//
// Workspace layout (under the stage's workspace root WS):
//   WS/sfm/images/           the usable photos (links, or upright/downscaled copies)
//   WS/sfm/masks/            their masks as staged (sfm/photo_masks.h), if any
//   WS/sfm/database.db       COLMAP's feature and match database
//   WS/sfm/vocab_tree.bin    vocabulary tree learnt from the photos (vocab_tree matcher)
//   WS/sfm/sparse/<k>/       COLMAP's models (several if the photos split)
//   WS/sfm/undistorted/      the result: images/ + sparse/ (PINHOLE), see
//                            core/undistorted_workspace.h; written atomically;
//                            with masks/ when photos have masks (core/image_mask.h)
//   WS/sfm/report.json       figures of the run (written last; sfm/sfm_report.h)
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/geodesy.h"
#include "core/reporter.h"
#include "core/sparse_model.h"
#include "sfm/image_inputs.h"
#include "sfm/sfm_options.h"
#include "sfm/sfm_plan.h"

namespace hos::sfm {

struct SfmPaths {
  std::filesystem::path root;  // WS/sfm
  std::filesystem::path images;
  std::filesystem::path masks;       // the staged masks (staged_mask_folder(images))
  std::filesystem::path thumbnails;  // NAME.jpg per usable photo, for the run report
  std::filesystem::path database;
  std::filesystem::path vocab_tree;
  std::filesystem::path image_lists;  // the photos of each feature_extractor run
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

// A usable photo the model does not contain, and what COLMAP made of it.
struct UnregisteredPhoto {
  std::string name;
  int best_matches = 0;  // most verified matches with any one other photo
  int other_model = -1;  // the model it is in instead, -1 if none
};

// One camera of the model and its principal point after the final
// adjustment: estimated, or the centre kept and why.
struct CameraPrincipalPoint {
  int camera_id = 0;
  int width = 0;
  int height = 0;
  int images = 0;  // registered photos of the camera
  bool estimated = false;
  double offset_px = 0.0;  // from the image centre, when estimated
  std::string reason;      // why the centre was kept; empty when estimated
};

struct SfmResult {
  std::filesystem::path undistorted;  // the undistorted workspace
  int images_given = 0;
  int images_registered = 0;
  std::vector<std::string> unregistered;               // names of usable photos COLMAP did not register
  std::vector<UnregisteredPhoto> unregistered_photos;  // the same, with what COLMAP made of them
  // images_registered / images_given, and a warning text when below
  // options' registered_warning_fraction (coverage_warning_text).
  double registered_fraction = 0.0;
  std::string coverage_warning;
  std::vector<SkippedInput> skipped;  // files of the folder that were not usable
  // Every usable photo's EXIF GPS position (report.json "photos" as
  // core/photo_gps_json.h writes it, read by the texture stage to place the
  // model: texture/geo_alignment.h).
  std::vector<PhotoGps> photos;
  std::vector<VideoClipSummary> videos;  // video clips among the photos: frames kept and why
  int masked_photos = 0;                 // photos given with a mask (sfm.masks or PHOTO.png)
  int masks_undistorted = 0;             // masks written into the undistorted workspace
  std::int64_t points = 0;
  double mean_reprojection_error_px = 0.0;
  double mean_track_length = 0.0;
  // The principal point after the final adjustment (options'
  // principal_point_max_offset): its largest distance from the image centre
  // over the cameras (pixels; 0 when not estimated), and whether the estimate
  // was kept (else the centre was).
  double principal_point_offset_px = 0.0;
  bool principal_point_estimated = false;              // for at least one camera
  std::vector<CameraPrincipalPoint> principal_points;  // per camera (empty when the step did not run)
  std::vector<SfmModelSummary> models;                 // every model COLMAP produced
  int used_model = 0;
  std::string matcher;      // plan.matcher, or "existing model"
  SfmPlan plan;             // what COLMAP was asked to do (empty for an existing model)
  int cameras_planned = 0;  // cameras the feature extraction runs create
  // Photos with a position prior in COLMAP's database after feature
  // extraction; -1 when not checked (no photo had GPS EXIF).
  int position_priors = -1;
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

// Throws InputError naming the photo and both sizes when a registered
// image of an existing model (--sparse) is not the size of its camera.
void check_model_image_sizes(const SparseModel& model, const std::filesystem::path& images);

// "only 3 of 12 photos (25%) registered: ..." with why the others did not
// (a separate model, too few verified matches with any one photo, or
// matched but not placed) and what to do.
std::string coverage_warning_text(const SfmResult& result, int min_pose_inliers);

// Runs the stage. Throws InputError (bad photo folder or model), StageError
// (COLMAP missing or failed, too few images registered), Cancelled.
SfmResult run_sfm(const SfmInput& input, const SfmOptions& options, Reporter& reporter);

// "times: total 41.2 s; prepare_images 0.3 s; feature_extractor 12.0 s; ...".
std::string step_times_text(const SfmResult& result);

// A few lines for the terminal: registered/given, points, errors, the
// matching plan, per-step times.
std::vector<std::string> sfm_summary_lines(const SfmResult& result);

}  // namespace hos::sfm
