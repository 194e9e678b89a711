#include "sfm/sfm_report.h"

#include "core/json_report.h"
#include "core/photo_gps_json.h"

namespace hos::sfm {
namespace {

using Json = nlohmann::ordered_json;

// Each element of j[key], when j has the key, as from_json makes it.
template <typename T, typename FromJson>
void read_list(const Json& j, const char* key, std::vector<T>& list, FromJson from_json) {
  if (const auto it = j.find(key); it != j.end()) {
    for (const Json& element : it->get<std::vector<Json>>()) list.push_back(from_json(element));
  }
}

VideoClipReport video_report(const VideoClipSummary& clip) {
  const VideoFrameSelection& s = clip.selection;
  return {clip.file.string(), clip.name, s.frames_read, s.fps, s.kept, s.too_little_motion, s.blurred, s.over_limit};
}

SfmPlanReport plan_report(const SfmPlan& plan) {
  SfmPlanReport p{plan.matcher,
                  plan.matcher_reason,
                  plan.spatial_ignore_z,
                  plan.max_num_features,
                  plan.max_num_matches,
                  plan.vocab_tree_words,
                  {}};
  for (const ExtractionRun& run : plan.extractions) {
    p.extractions.push_back({static_cast<int>(run.names.size()), run.description, run.single_camera,
                             run.sift_max_image_size, run.sift_upsample});
  }
  return p;
}

Json video_json(const VideoClipReport& v) {
  return {{"file", v.file},
          {"name", v.name},
          {"frames", v.frames},
          {"fps", v.fps},
          {"kept", v.kept_frames.size()},
          {"kept_frames", v.kept_frames},
          {"dropped_too_little_motion", v.dropped_too_little_motion},
          {"dropped_blurred", v.dropped_blurred},
          {"dropped_over_max_frames", v.dropped_over_max_frames}};
}

Json camera_json(const CameraPrincipalPoint& c) {
  return {{"camera_id", c.camera_id}, {"width", c.width},         {"height", c.height}, {"images", c.images},
          {"estimated", c.estimated}, {"offset_px", c.offset_px}, {"reason", c.reason}};
}

Json plan_json(const SfmPlanReport& plan) {
  Json extractions = Json::array();
  for (const ExtractionReport& run : plan.extractions) {
    extractions.push_back({{"photos", run.photos},
                           {"description", run.description},
                           {"single_camera", run.single_camera},
                           {"sift_max_image_size", run.sift_max_image_size},
                           {"sift_upsample", run.sift_upsample}});
  }
  return {{"matcher", plan.matcher},
          {"matcher_reason", plan.matcher_reason},
          {"spatial_ignore_z", plan.spatial_ignore_z},
          {"max_num_features", plan.max_num_features},
          {"max_num_matches", plan.max_num_matches},
          {"vocab_tree_words", plan.vocab_tree_words},
          {"extractions", extractions}};
}

// The lists of the report, each element as its own object.
void add_lists_json(const SfmReport& r, Json& j) {
  j["unregistered_photos"] = Json::array();
  for (const UnregisteredPhoto& p : r.unregistered_photos) {
    j["unregistered_photos"].push_back(
        {{"name", p.name}, {"best_verified_matches", p.best_matches}, {"other_model", p.other_model}});
  }
  j["skipped"] = Json::array();
  for (const SkippedInput& s : r.skipped) j["skipped"].push_back({{"file", s.file.string()}, {"reason", s.reason}});
  j["photos"] = photo_gps_json(r.photos);
  if (!r.videos.empty()) {
    j["videos"] = Json::array();
    for (const VideoClipReport& v : r.videos) j["videos"].push_back(video_json(v));
  }
}

UnregisteredPhoto unregistered_from_json(const Json& j) {
  UnregisteredPhoto p;
  read_key(j, "name", p.name);
  read_key(j, "best_verified_matches", p.best_matches);
  read_key(j, "other_model", p.other_model);
  return p;
}

SkippedInput skipped_from_json(const Json& j) {
  SkippedInput s;
  std::string file;
  read_key(j, "file", file);
  s.file = file;
  read_key(j, "reason", s.reason);
  return s;
}

VideoClipReport video_from_json(const Json& j) {
  VideoClipReport v;
  read_key(j, "file", v.file);
  read_key(j, "name", v.name);
  read_key(j, "frames", v.frames);
  read_key(j, "fps", v.fps);
  read_key(j, "kept_frames", v.kept_frames);
  read_key(j, "dropped_too_little_motion", v.dropped_too_little_motion);
  read_key(j, "dropped_blurred", v.dropped_blurred);
  read_key(j, "dropped_over_max_frames", v.dropped_over_max_frames);
  return v;
}

CameraPrincipalPoint camera_from_json(const Json& j) {
  CameraPrincipalPoint c;
  read_key(j, "camera_id", c.camera_id);
  read_key(j, "width", c.width);
  read_key(j, "height", c.height);
  read_key(j, "images", c.images);
  read_key(j, "estimated", c.estimated);
  read_key(j, "offset_px", c.offset_px);
  read_key(j, "reason", c.reason);
  return c;
}

SfmModelSummary model_from_json(const Json& j) {
  SfmModelSummary m;
  read_key(j, "index", m.index);
  read_key(j, "images", m.images);
  read_key(j, "points", m.points);
  return m;
}

ExtractionReport extraction_from_json(const Json& j) {
  ExtractionReport e;
  read_key(j, "photos", e.photos);
  read_key(j, "description", e.description);
  read_key(j, "single_camera", e.single_camera);
  read_key(j, "sift_max_image_size", e.sift_max_image_size);
  read_key(j, "sift_upsample", e.sift_upsample);
  return e;
}

SfmPlanReport plan_from_json(const Json& j) {
  SfmPlanReport p;
  read_key(j, "matcher", p.matcher);
  read_key(j, "matcher_reason", p.matcher_reason);
  read_key(j, "spatial_ignore_z", p.spatial_ignore_z);
  read_key(j, "max_num_features", p.max_num_features);
  read_key(j, "max_num_matches", p.max_num_matches);
  read_key(j, "vocab_tree_words", p.vocab_tree_words);
  read_list(j, "extractions", p.extractions, extraction_from_json);
  return p;
}

void read_lists(const Json& j, SfmReport& r) {
  read_key(j, "unregistered", r.unregistered);
  read_list(j, "unregistered_photos", r.unregistered_photos, unregistered_from_json);
  read_list(j, "skipped", r.skipped, skipped_from_json);
  if (const auto photos = j.find("photos"); photos != j.end()) r.photos = photo_gps_from_json(*photos);
  read_list(j, "videos", r.videos, video_from_json);
  read_list(j, "models", r.models, model_from_json);
}

SfmReport report_from_json(const Json& j) {
  SfmReport r;
  read_key(j, "images_given", r.images_given);
  read_key(j, "images_registered", r.images_registered);
  read_key(j, "registered_fraction", r.registered_fraction);
  read_key(j, "warning", r.warning);
  read_lists(j, r);
  read_key(j, "masked_photos", r.masked_photos);
  read_key(j, "masks_undistorted", r.masks_undistorted);
  read_key(j, "points", r.points);
  read_key(j, "mean_reprojection_error_px", r.mean_reprojection_error_px);
  read_key(j, "mean_track_length", r.mean_track_length);
  if (const auto pp = j.find("principal_point"); pp != j.end()) {
    read_key(*pp, "estimated", r.principal_point_estimated);
    read_key(*pp, "offset_px", r.principal_point_offset_px);
    read_list(*pp, "cameras", r.principal_points, camera_from_json);
  }
  read_key(j, "used_model", r.used_model);
  read_key(j, "matcher", r.matcher);
  if (const auto plan = j.find("plan"); plan != j.end()) r.plan = plan_from_json(*plan);
  read_key(j, "cameras_planned", r.cameras_planned);
  read_key(j, "position_priors", r.position_priors);
  read_key(j, "colmap_version", r.colmap_version);
  read_key(j, "step_seconds", r.step_seconds);
  read_key(j, "total_seconds", r.total_seconds);
  return r;
}

}  // namespace

SfmReport sfm_report(const SfmResult& result) {
  SfmReport r;
  r.images_given = result.images_given;
  r.images_registered = result.images_registered;
  r.registered_fraction = result.registered_fraction;
  r.warning = result.coverage_warning;
  r.unregistered = result.unregistered;
  r.unregistered_photos = result.unregistered_photos;
  r.skipped = result.skipped;
  r.photos = result.photos;
  for (const VideoClipSummary& clip : result.videos) r.videos.push_back(video_report(clip));
  r.masked_photos = result.masked_photos;
  r.masks_undistorted = result.masks_undistorted;
  r.points = result.points;
  r.mean_reprojection_error_px = result.mean_reprojection_error_px;
  r.mean_track_length = result.mean_track_length;
  r.principal_point_estimated = result.principal_point_estimated;
  r.principal_point_offset_px = result.principal_point_offset_px;
  r.principal_points = result.principal_points;
  r.models = result.models;
  r.used_model = result.used_model;
  r.matcher = result.matcher;
  if (!result.plan.matcher.empty()) r.plan = plan_report(result.plan);
  r.cameras_planned = result.cameras_planned;
  r.position_priors = result.position_priors;
  r.colmap_version = result.colmap_version;
  r.step_seconds = result.step_seconds;
  r.total_seconds = result.total_seconds;
  return r;
}

nlohmann::ordered_json to_json(const SfmReport& r) {
  Json j;
  j["images_given"] = r.images_given;
  j["images_registered"] = r.images_registered;
  j["registered_fraction"] = r.registered_fraction;
  if (!r.warning.empty()) j["warning"] = r.warning;
  j["unregistered"] = r.unregistered;
  add_lists_json(r, j);
  j["masked_photos"] = r.masked_photos;
  j["masks_undistorted"] = r.masks_undistorted;
  j["points"] = r.points;
  j["mean_reprojection_error_px"] = r.mean_reprojection_error_px;
  j["mean_track_length"] = r.mean_track_length;
  j["principal_point"] = {{"estimated", r.principal_point_estimated},
                          {"offset_px", r.principal_point_offset_px},
                          {"cameras", Json::array()}};
  for (const CameraPrincipalPoint& c : r.principal_points) j["principal_point"]["cameras"].push_back(camera_json(c));
  j["models"] = Json::array();
  for (const SfmModelSummary& m : r.models) {
    j["models"].push_back({{"index", m.index}, {"images", m.images}, {"points", m.points}});
  }
  j["used_model"] = r.used_model;
  j["matcher"] = r.matcher;
  if (r.plan) j["plan"] = plan_json(*r.plan);
  j["cameras_planned"] = r.cameras_planned;
  if (r.position_priors >= 0) j["position_priors"] = r.position_priors;
  j["colmap_version"] = r.colmap_version;
  j["step_seconds"] = named_values_json(r.step_seconds);
  j["total_seconds"] = r.total_seconds;
  return j;
}

SfmReport read_sfm_report(const std::filesystem::path& path) { return read_json_report(path, report_from_json); }

void write_sfm_report(const SfmResult& result, const std::filesystem::path& file) {
  write_json_report(file, to_json(sfm_report(result)));
}

}  // namespace hos::sfm
