#include "sfm/sfm.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <sstream>

#include "core/atomic_file.h"
#include "core/colmap_io.h"
#include "core/error.h"
#include "core/image_mask.h"
#include "core/sparse_model.h"
#include "core/stopwatch.h"
#include "core/undistorted_workspace.h"
#include "sfm/colmap_database.h"
#include "sfm/colmap_runner.h"
#include "sfm/colmap_steps.h"
#include "sfm/photo_masks.h"
#include "sfm/principal_point_evidence.h"

namespace hos::sfm {
namespace fs = std::filesystem;
namespace {

constexpr std::size_t kMaxListed = 20;  // names listed in messages
std::string list_names(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < kMaxListed; ++i) out += (i ? ", " : "") + names[i];
  if (names.size() > kMaxListed) out += format_message(" and ", names.size() - kMaxListed, " more");
  return out;
}

void add_step_time(SfmResult& result, const std::string& step, double seconds) {
  for (auto& [name, total] : result.step_seconds) {
    if (name == step) {
      total += seconds;
      return;
    }
  }
  result.step_seconds.emplace_back(step, seconds);
}

bool has_model_files(const fs::path& dir) { return fs::exists(dir / "cameras.bin") || fs::exists(dir / "cameras.txt"); }

// Models in numbered subfolders, as the mapper writes them.
std::vector<std::pair<int, fs::path>> numbered_models(const fs::path& dir) {
  std::vector<std::pair<int, fs::path>> out;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_directory() || name.empty() ||
        !std::all_of(name.begin(), name.end(), [](unsigned char c) { return std::isdigit(c); })) {
      continue;
    }
    if (has_model_files(entry.path())) out.emplace_back(std::stoi(name), entry.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

void require_ok(const ColmapStepResult& step, const std::string& what) {
  if (step.exit_code != 0) {
    throw StageError("sfm", "COLMAP " + what + " failed (exit code " + std::to_string(step.exit_code) +
                                "); the end of its output (full log in the stage log):" + format_tail(step.last_lines));
  }
}

void fill_model_figures(const SparseModel& model, SfmResult& result) {
  const SparseModelStats stats = compute_stats(model);
  result.images_registered = stats.num_images;
  result.points = stats.num_points;
  result.mean_reprojection_error_px = stats.mean_reprojection_error_px;
  result.mean_track_length = stats.mean_track_length;
}

bool is_undistorted(const SparseModel& model) {
  return std::all_of(model.cameras.begin(), model.cameras.end(), [](const auto& item) {
    const Camera& c = item.second;
    return (c.model == CameraModel::kPinhole || c.model == CameraModel::kSimplePinhole);
  });
}

// COLMAP's undistorter writes run scripts and a stereo/ folder for its own
// dense stereo; hos does not use them.
void remove_colmap_extras(const fs::path& dir) {
  std::error_code ec;
  fs::remove_all(dir / "stereo", ec);
  fs::remove(dir / "run-colmap-geometric.sh", ec);
  fs::remove(dir / "run-colmap-photometric.sh", ec);
}

void undistort_with_colmap(const ColmapInfo& colmap,
                           const fs::path& images,
                           const fs::path& model,
                           const fs::path& output,
                           std::int64_t num_images,
                           Reporter& reporter,
                           SfmResult& result) {
  ColmapStep step{"image_undistorter",
                  {"--image_path", images.string(), "--input_path", model.string(), "--output_path", output.string(),
                   "--output_type", "COLMAP"},
                  "undistorting images",
                  num_images};
  const ColmapStepResult run = run_colmap_step(colmap, step, reporter);
  require_ok(run, "image_undistorter");
  add_step_time(result, "image_undistorter", run.seconds);
  remove_colmap_extras(output);
}

void clear_previous_run(const SfmPaths& paths) {
  std::error_code ec;
  for (const auto& p : {paths.report, paths.undistorted, paths.sparse, paths.database, paths.vocab_tree, paths.images,
                        paths.masks, paths.thumbnails, paths.image_lists}) {
    fs::remove_all(p, ec);
  }
  fs::remove(paths.database.string() + "-shm", ec);
  fs::remove(paths.database.string() + "-wal", ec);
}

// The masks warped as the photos were (mvs and texture read them there).
void write_undistorted_masks(const SparseModel& distorted,
                             const UndistortedWorkspace& undistorted,
                             const fs::path& masks,
                             Reporter& reporter,
                             SfmResult& result) {
  const auto started = Clock::now();
  result.masks_undistorted = undistort_masks(distorted, undistorted.model, masks, workspace_mask_folder(undistorted));
  add_step_time(result, "undistort_masks", seconds_since(started));
  reporter.debug(format_message("sfm: ", result.masks_undistorted, " masks undistorted"));
}

// Existing-model input: check it, then undistort it (or copy it when it is
// already undistorted) into the workspace.
SfmResult import_existing_model(const SfmInput& input,
                                const SfmOptions& options,
                                const SfmPaths& paths,
                                Reporter& reporter) {
  fs::path model_dir = input.existing_model;
  if (!fs::is_directory(model_dir)) throw InputError(model_dir.string(), "sparse model folder does not exist");
  if (!fs::is_directory(input.images)) throw InputError(input.images.string(), "image folder does not exist");
  SparseModel model;
  if (has_model_files(model_dir)) {
    model = read_colmap_model(model_dir);
  } else {
    // A mapper output folder (0/, 1/, ...): the largest model, as after SfM.
    const auto models = numbered_models(model_dir);
    if (models.empty()) {
      throw InputError(model_dir.string(), "holds no COLMAP model (cameras/images/points3D .bin or .txt)");
    }
    fs::path best_dir;
    for (const auto& [index, dir] : models) {
      SparseModel candidate = read_colmap_model(dir);
      if (best_dir.empty() || candidate.images.size() > model.images.size()) {
        model = std::move(candidate);
        best_dir = dir;
      }
    }
    model_dir = best_dir;
  }
  reporter.info("using the existing sparse model " + model_dir.string());
  check_model_image_sizes(model, input.images);
  SfmResult result;
  result.matcher = "existing model";
  result.images_given = static_cast<int>(model.images.size());
  result.models.push_back({0, static_cast<int>(model.images.size()), static_cast<std::int64_t>(model.points.size())});
  fill_model_figures(model, result);
  if (result.images_registered < options.min_registered_images) {
    throw InputError(model_dir.string(),
                     format_message("has only ", result.images_registered, " registered images (need ",
                                    options.min_registered_images, ")"));
  }
  write_folder_atomically(paths.undistorted, [&](const fs::path& tmp) {
    if (is_undistorted(model)) {
      fs::create_directories(tmp / "images");
      reporter.begin("copying images", static_cast<std::int64_t>(model.images.size()));
      for (const auto& [id, image] : model.images) {
        reporter.throw_if_cancelled();
        const fs::path target = tmp / "images" / image.name;
        fs::create_directories(target.parent_path());
        fs::copy_file(input.images / image.name, target, fs::copy_options::overwrite_existing);
        reporter.advance();
      }
      reporter.end();
      write_colmap_model(model, tmp / "sparse", ColmapFormat::kBinary);
    } else {
      const ColmapInfo colmap = locate_colmap(options.colmap);
      result.colmap_version = colmap.version;
      undistort_with_colmap(colmap, input.images, model_dir, tmp, static_cast<std::int64_t>(model.images.size()),
                            reporter, result);
    }
    const UndistortedWorkspace undistorted = load_undistorted_workspace(tmp);  // the consumers' own check
    // The masks of the model's images: in sfm.masks, else beside the images.
    write_undistorted_masks(model, undistorted, options.mask_folder().empty() ? input.images : options.mask_folder(),
                            reporter, result);
    result.masked_photos = result.masks_undistorted;
    if (result.masked_photos > 0) {
      reporter.info(format_message("masks: ", result.masked_photos, " of ", model.images.size(),
                                   " images of the model have a mask"));
    }
  });
  result.undistorted = paths.undistorted;
  return result;
}

void prepare_workspace(const SfmPaths& paths) {
  std::error_code ec;
  fs::create_directories(paths.root, ec);
  if (ec) throw OutputError(paths.root.string(), "cannot create the workspace folder: " + ec.message());
  clear_previous_run(paths);
}

ImageInputs stage_photos(
    const SfmInput& input, const SfmOptions& options, const SfmPaths& paths, Reporter& reporter, SfmResult& result) {
  const auto started = Clock::now();
  // The workspace may lie inside the photo folder: its files are not photos.
  ImageInputs inputs =
      prepare_images(input.images, paths.images, options, reporter, paths.thumbnails, {input.workspace});
  result.step_seconds.emplace_back("prepare_images", seconds_since(started));
  result.skipped = inputs.skipped;
  for (const StagedImage& image : inputs.images) result.photos.push_back({image.name, image.gps});
  result.videos = inputs.videos;
  result.images_given = static_cast<int>(inputs.images.size());
  result.masked_photos = inputs.masked_photos();
  return inputs;
}

ColmapRunContext run_context(const ImageInputs& inputs,
                             const SfmOptions& options,
                             const ColmapInfo& colmap,
                             const SfmPaths& paths) {
  ColmapRunContext context;
  context.database = paths.database;
  context.images = paths.images;
  context.sparse = paths.sparse;
  context.vocab_tree = paths.vocab_tree;
  context.masks = inputs.mask_folder;
  context.gpu = options.use_gpu == "yes" || (options.use_gpu == "auto" && colmap.cuda);
  context.num_images = static_cast<std::int64_t>(inputs.images.size());
  return context;
}

int planned_cameras(const SfmPlan& plan) {
  int cameras = 0;
  for (const ExtractionRun& run : plan.extractions) {
    cameras += run.single_camera ? 1 : static_cast<int>(run.names.size());
  }
  return cameras;
}

void announce_plan(const ColmapRunContext& context,
                   const ColmapInfo& colmap,
                   const SfmOptions& options,
                   const SfmResult& result,
                   Reporter& reporter) {
  const SfmPlan& plan = result.plan;
  reporter.info(format_message(context.num_images, " photos, ", result.cameras_planned,
                               result.cameras_planned == 1 ? " camera" : " cameras", " (", options.camera_model,
                               ", sfm.camera_mode ", options.camera_mode, "), COLMAP ", colmap.version,
                               context.gpu ? " with GPU" : " on the CPU"));
  for (const ExtractionRun& run : plan.extractions) {
    reporter.info(format_message("  ", run.description, ": ", run.single_camera ? "one camera" : "one camera per photo",
                                 ", SIFT at most ", run.sift_max_image_size, " px",
                                 run.sift_upsample ? " (and 2x)" : ""));
  }
  reporter.info(format_message(plan.max_num_features, " features per photo, ", plan.max_num_matches,
                               " matches per pair; ", plan.matcher, " matching (", plan.matcher_reason, ")"));
}

// Runs one COLMAP command, fails the stage on an error exit, keeps its time
// (summed over the runs of one command).
void run_timed(const ColmapInfo& colmap, const ColmapStep& step, Reporter& reporter, SfmResult& result) {
  const ColmapStepResult run = run_colmap_step(colmap, step, reporter);
  require_ok(run, step.command);
  add_step_time(result, step.command, run.seconds);
}

// One feature_extractor run per planned extraction, all into one database:
// each group of photos gets its SIFT size and its camera.
void extract_features(const ColmapInfo& colmap,
                      const ColmapRunContext& context,
                      const SfmOptions& options,
                      const SfmPaths& paths,
                      Reporter& reporter,
                      SfmResult& result) {
  fs::create_directories(paths.image_lists);
  for (std::size_t k = 0; k < result.plan.extractions.size(); ++k) {
    const ExtractionRun& run = result.plan.extractions[k];
    const fs::path list = paths.image_lists / format_message("extraction_", k, ".txt");
    write_atomically(list, [&](const fs::path& tmp) {
      std::ofstream out(tmp, std::ios::binary);
      out << image_list_file_text(run);
      if (!out) throw OutputError(list.string(), "the list of photos for COLMAP's feature extraction");
    });
    run_timed(colmap, feature_extraction_step(context, run, list, result.plan, options), reporter, result);
  }
}

// Spatial matching needs COLMAP to have read each photo's position: checks
// the priors in the database and falls back when they are missing.
void check_position_priors(const PhotoSetFacts& facts,
                           const SfmOptions& options,
                           const SfmPaths& paths,
                           Reporter& reporter,
                           SfmResult& result) {
  if (facts.photos_with_gps == 0) return;
  int priors = 0;
  for (const DatabaseImage& image : read_database_images(paths.database)) priors += image.position_prior ? 1 : 0;
  result.position_priors = priors;
  reporter.debug(format_message(facts.photos_with_gps, " photos with GPS EXIF, ", priors,
                                " position priors in COLMAP's database"));
  if (fall_back_from_spatial(result.plan, facts, priors, options)) {
    reporter.warn("sfm: " + result.plan.matcher + " matching instead of spatial: " + result.plan.matcher_reason);
    result.matcher = result.plan.matcher;
  }
}

// Reads every model the mapper wrote and picks the largest; returns its folder.
fs::path select_largest_model(const std::vector<std::pair<int, fs::path>>& models,
                              const ImageInputs& inputs,
                              Reporter& reporter,
                              SfmResult& result) {
  SparseModel best;
  fs::path best_dir;
  std::vector<SparseModel> all;
  for (const auto& [index, dir] : models) {
    all.push_back(read_colmap_model(dir));
    const SparseModel& model = all.back();
    result.models.push_back(
        {index, static_cast<int>(model.images.size()), static_cast<std::int64_t>(model.points.size())});
    if (best_dir.empty() || model.images.size() > best.images.size()) {
      best = model;
      best_dir = dir;
      result.used_model = index;
    }
  }
  fill_model_figures(best, result);
  for (const auto& image : inputs.images) {
    if (best.find_image(image.name)) continue;
    result.unregistered.push_back(image.name);
    UnregisteredPhoto photo{image.name, 0, -1};
    for (std::size_t k = 0; k < all.size(); ++k) {
      if (all[k].find_image(image.name)) photo.other_model = result.models[k].index;
    }
    result.unregistered_photos.push_back(photo);
  }
  if (result.models.size() > 1) {
    std::string others;
    for (const auto& m : result.models) {
      if (m.index != result.used_model)
        others += format_message(others.empty() ? "" : ", ", "model ", m.index, " (", m.images, " images)");
    }
    reporter.warn(format_message("COLMAP split the photos into ", result.models.size(), " models; using model ",
                                 result.used_model, " (", result.images_registered, " images), ignoring ", others));
  }
  return best_dir;
}

// Why each unregistered photo is missing: in another model, or matched no
// other photo well (its most verified matches with any one photo).
void explain_unregistered(const SfmPaths& paths, SfmResult& result) {
  if (result.unregistered_photos.empty()) return;
  const std::map<std::string, int> best = best_verified_matches(paths.database);
  for (UnregisteredPhoto& photo : result.unregistered_photos) {
    const auto found = best.find(photo.name);
    photo.best_matches = found == best.end() ? 0 : found->second;
  }
}

// How much of the capture the model uses; a loud warning below
// options.registered_warning_fraction.
void judge_coverage(const SfmOptions& options, Reporter& reporter, SfmResult& result) {
  result.registered_fraction = result.images_given > 0 ? double(result.images_registered) / result.images_given : 0.0;
  if (result.registered_fraction >= options.registered_warning_fraction) return;
  result.coverage_warning = coverage_warning_text(result, options.min_pose_inliers);
  reporter.warn("sfm: " + result.coverage_warning);
}

// The mapper, then the largest model; fails the stage when too few photos
// registered. Returns the chosen model's folder.
fs::path map_photos(const ColmapInfo& colmap,
                    const ColmapRunContext& context,
                    const SfmOptions& options,
                    const ImageInputs& inputs,
                    const SfmPaths& paths,
                    Reporter& reporter,
                    SfmResult& result) {
  fs::create_directories(context.sparse);
  const ColmapStepResult mapped = run_colmap_step(colmap, mapping_step(context, options), reporter);
  add_step_time(result, "mapper", mapped.seconds);
  const auto models = numbered_models(context.sparse);
  if (models.empty()) {
    throw StageError("sfm", format_message("COLMAP could not register the photos (no model from ", context.num_images,
                                           " photos): they may not overlap enough or lack texture. "
                                           "Photos of one object need 60-80% overlap between neighbours.",
                                           mapped.exit_code != 0
                                               ? " COLMAP mapper output ends with:" + format_tail(mapped.last_lines)
                                               : std::string()));
  }
  require_ok(mapped, "mapper");
  fs::path best_dir = select_largest_model(models, inputs, reporter, result);
  explain_unregistered(paths, result);
  if (result.images_registered < options.min_registered_images) {
    throw StageError("sfm", format_message("only ", result.images_registered, " of ", context.num_images,
                                           " photos registered (need ", options.min_registered_images,
                                           "): the photos may not overlap enough. Not registered: ",
                                           list_names(result.unregistered)));
  }
  judge_coverage(options, reporter, result);
  return best_dir;
}

// COLMAP's parameter layout: one focal length first for the SIMPLE_* and
// RADIAL* models, two for the others; the principal point follows.
void centre_principal_point(Camera& camera) {
  const std::string name = camera_model_name(camera.model);
  const std::size_t cx = name.rfind("SIMPLE_", 0) == 0 || name.rfind("RADIAL", 0) == 0 ? 1 : 2;
  camera.params.at(cx) = 0.5 * camera.width;
  camera.params.at(cx + 1) = 0.5 * camera.height;
}

// Which cameras may have their principal point estimated: those shared by
// enough registered photos.
std::vector<CameraPrincipalPoint> principal_point_candidates(const SparseModel& model, const SfmOptions& options) {
  std::map<int, int> photos;
  for (const auto& [id, image] : model.images) ++photos[image.camera_id];
  std::vector<CameraPrincipalPoint> cameras;
  for (const auto& [id, camera] : model.cameras) {
    CameraPrincipalPoint c;
    c.camera_id = id;
    c.width = camera.width;
    c.height = camera.height;
    c.images = photos[id];
    if (c.images < options.principal_point_min_images) {
      c.reason = format_message("centre kept: fewer photos than sfm.principal_point_min_images (",
                                options.principal_point_min_images, ")");
    }
    cameras.push_back(c);
  }
  return cameras;
}

bool is_candidate(const CameraPrincipalPoint& c) { return c.reason.empty(); }

// Keeps the centre of each candidate camera whose freed principal point fits
// its keypoints no better than noise would (the reason says so). COLMAP
// frees every camera's principal point or none, so each camera is judged on
// its own photos' keypoints: a one-photo camera's free principal point,
// which soaks up that photo's residuals, is no evidence for the others.
void keep_centres_without_evidence(const SparseModel& centred,
                                   const SparseModel& estimated,
                                   Reporter& reporter,
                                   std::vector<CameraPrincipalPoint>& cameras) {
  const std::map<int, ReprojectionFit> fits_centred = reprojection_fits(centred);
  const std::map<int, ReprojectionFit> fits_estimated = reprojection_fits(estimated);
  const auto fit_of = [](const std::map<int, ReprojectionFit>& fits, int camera_id) {
    const auto fit = fits.find(camera_id);
    return fit != fits.end() ? fit->second : ReprojectionFit{};
  };
  for (auto& c : cameras) {
    if (!is_candidate(c)) continue;
    const ReprojectionFit before = fit_of(fits_centred, c.camera_id);
    const ReprojectionFit after = fit_of(fits_estimated, c.camera_id);
    const PrincipalPointEvidence evidence = principal_point_evidence(before, after, 2);
    reporter.debug(format_message("sfm: camera ", c.camera_id, " with its principal point free: squared reprojection ",
                                  "error ", before.sum_squared_px, " -> ", after.sum_squared_px, " px^2 over ",
                                  after.observations, " keypoints; chi-square ", evidence.chi_square, ", chance ",
                                  evidence.chance));
    if (evidence.supported) continue;
    c.reason = format_message("centre kept: the estimate fits the keypoints no better than noise would (chance ",
                              evidence.chance, ", needs < ", kPrincipalPointSignificance, ")");
  }
}

// The final bundle adjustment that also estimates the principal point of
// each camera shared by at least options.principal_point_min_images photos,
// kept when it fits the keypoints better than noise would
// (sfm/principal_point_evidence.h) and stays within
// options.principal_point_max_offset of the image centre (an estimate farther
// away means the photos did not constrain it). COLMAP refines every camera's
// principal point or none, so when some cameras keep their centre, they get
// it back and a second adjustment refines the rest of the model around it.
// Returns the folder of the model to use.
fs::path adjust_principal_point(const ColmapInfo& colmap,
                                const fs::path& model_dir,
                                const SfmOptions& options,
                                const SfmPaths& paths,
                                Reporter& reporter,
                                SfmResult& result) {
  if (options.principal_point_max_offset <= 0) return model_dir;
  const SparseModel mapped = read_colmap_model(model_dir);
  result.principal_points = principal_point_candidates(mapped, options);
  auto& cameras = result.principal_points;
  if (std::none_of(cameras.begin(), cameras.end(), is_candidate)) return model_dir;
  fs::path adjusted_dir = paths.sparse / "principal_point";
  fs::remove_all(adjusted_dir);
  fs::create_directories(adjusted_dir);
  const ColmapStepResult run = run_colmap_step(colmap, principal_point_step(model_dir, adjusted_dir, true), reporter);
  add_step_time(result, "bundle_adjuster", run.seconds);
  if (run.exit_code != 0) {
    for (auto& c : cameras) c.reason = "centre kept: the bundle adjustment failed";
    reporter.warn("sfm: the principal point's bundle adjustment failed; the image centre is kept" +
                  format_tail(run.last_lines));
    return model_dir;
  }
  SparseModel adjusted = read_colmap_model(adjusted_dir);
  keep_centres_without_evidence(mapped, adjusted, reporter, cameras);
  for (auto& c : cameras) {
    Camera& camera = adjusted.cameras.at(c.camera_id);
    const double offset =
        std::hypot(camera.principal_x() - 0.5 * camera.width, camera.principal_y() - 0.5 * camera.height);
    if (is_candidate(c) && offset > options.principal_point_max_offset * std::max(camera.width, camera.height)) {
      c.reason = format_message("centre kept: estimated ", offset,
                                " px off centre, more than sfm.principal_point_max_offset (",
                                options.principal_point_max_offset, " of the longer side)");
      reporter.warn(format_message("sfm: the principal point of camera ", c.camera_id, " was estimated ", offset,
                                   " px from the image centre: the photos do not constrain it; the centre is kept"));
    }
    c.estimated = is_candidate(c);
    if (c.estimated) {
      c.offset_px = offset;
      result.principal_point_offset_px = std::max(result.principal_point_offset_px, offset);
    } else {
      centre_principal_point(camera);
    }
  }
  const auto estimated = std::count_if(cameras.begin(), cameras.end(), [](const auto& c) { return c.estimated; });
  if (estimated == 0) return model_dir;
  result.principal_point_estimated = true;
  if (estimated == static_cast<std::ptrdiff_t>(cameras.size())) {
    fill_model_figures(adjusted, result);
    return adjusted_dir;
  }
  // Some cameras keep the centre: the model again around it.
  const fs::path centred_dir = paths.sparse / "principal_point_centred";
  fs::path final_dir = paths.sparse / "principal_point_final";
  for (const fs::path& dir : {centred_dir, final_dir}) {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  write_colmap_model(adjusted, centred_dir, ColmapFormat::kBinary);
  const ColmapStepResult again = run_colmap_step(colmap, principal_point_step(centred_dir, final_dir, false), reporter);
  add_step_time(result, "bundle_adjuster", again.seconds);
  if (again.exit_code != 0) {
    reporter.warn("sfm: the bundle adjustment after the principal point failed; the image centre is kept" +
                  format_tail(again.last_lines));
    for (auto& c : cameras)
      c = {c.camera_id, c.width, c.height, c.images, false, 0.0, "centre kept: adjustment failed"};
    result.principal_point_estimated = false;
    result.principal_point_offset_px = 0;
    return model_dir;
  }
  fill_model_figures(read_colmap_model(final_dir), result);
  return final_dir;
}

}  // namespace

void check_model_image_sizes(const SparseModel& model, const fs::path& images) {
  for (const auto& [id, image] : model.images) {
    const fs::path file = images / image.name;
    if (!fs::exists(file)) throw InputError(file.string(), "image of the sparse model is missing");
    const Camera& camera = model.camera_of(image);
    // The size COLMAP reads: the stored pixels, EXIF orientation not applied.
    const cv::Mat photo = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
    if (photo.empty()) throw InputError(file.string(), "image of the sparse model cannot be decoded");
    if (photo.cols != camera.width || photo.rows != camera.height) {
      throw InputError(file.string(),
                       format_message("is ", photo.cols, "x", photo.rows, " pixels but its camera (", camera.id,
                                      ") in the sparse model is ", camera.width, "x", camera.height,
                                      ": the model was made from other (or resized) photos; give the photos "
                                      "the model was made from, or run without --sparse"));
    }
  }
}

std::string coverage_warning_text(const SfmResult& r, int min_pose_inliers) {
  std::vector<std::string> unmatched, separate, unplaced;
  int most_matches = 0;
  for (const UnregisteredPhoto& photo : r.unregistered_photos) {
    if (photo.other_model >= 0) {
      separate.push_back(photo.name);
    } else if (photo.best_matches < min_pose_inliers) {
      unmatched.push_back(photo.name);
      most_matches = std::max(most_matches, photo.best_matches);
    } else {
      unplaced.push_back(photo.name);
    }
  }
  const int percent = static_cast<int>(std::lround(100.0 * r.registered_fraction));
  std::string text = format_message("only ", r.images_registered, " of ", r.images_given, " photos (", percent,
                                    "%) registered: the model leaves out ", r.images_given - r.images_registered);
  if (!unmatched.empty()) {
    text +=
        format_message("; ", unmatched.size(), " matched no other photo well (at most ", most_matches,
                       " verified matches with any one photo, a photo needs sfm.min_pose_inliers = ", min_pose_inliers,
                       "): ", list_names(unmatched));
  }
  if (!separate.empty()) {
    text +=
        format_message("; ", separate.size(),
                       " form separate models that share too few matches with the used one: ", list_names(separate));
  }
  if (!unplaced.empty()) {
    text += format_message("; ", unplaced.size(),
                           " matched other photos but did not fit the model: ", list_names(unplaced));
  }
  return text +
         ". Too little overlap: take more photos between these and the others (60-80% overlap between neighbours)";
}

PrincipalPointOffset largest_principal_point_offset(const SparseModel& model) {
  PrincipalPointOffset largest;
  for (const auto& [id, camera] : model.cameras) {
    const double pixels =
        std::hypot(camera.principal_x() - 0.5 * camera.width, camera.principal_y() - 0.5 * camera.height);
    const double fraction = pixels / std::max(1, std::max(camera.width, camera.height));
    if (fraction > largest.fraction) largest = {pixels, fraction};
  }
  return largest;
}

std::string step_times_text(const SfmResult& r) {
  std::ostringstream times;
  times << std::fixed << std::setprecision(1) << "times: total " << r.total_seconds << " s";
  for (const auto& [name, seconds] : r.step_seconds) times << "; " << name << " " << seconds << " s";
  return times.str();
}

SfmPaths sfm_paths(const fs::path& workspace) {
  SfmPaths p;
  p.root = workspace / "sfm";
  p.images = p.root / "images";
  p.masks = staged_mask_folder(p.images);
  p.thumbnails = p.root / "thumbnails";
  p.database = p.root / "database.db";
  p.vocab_tree = p.root / "vocab_tree.bin";
  p.image_lists = p.root / "image_lists";
  p.sparse = p.root / "sparse";
  p.undistorted = p.root / "undistorted";
  p.report = p.root / "report.json";
  return p;
}

SfmResult run_sfm(const SfmInput& input, const SfmOptions& options, Reporter& reporter) {
  const auto started = Clock::now();
  options.validate();
  const SfmPaths paths = sfm_paths(input.workspace);
  prepare_workspace(paths);
  if (!input.existing_model.empty()) {
    SfmResult result = import_existing_model(input, options, paths, reporter);
    result.total_seconds = seconds_since(started);
    return result;
  }

  // Inputs first: a bad photo folder is reported even where COLMAP is missing.
  SfmResult result;
  const ImageInputs inputs = stage_photos(input, options, paths, reporter, result);
  const ColmapInfo colmap = locate_colmap(options.colmap);
  result.colmap_version = colmap.version;
  const ColmapRunContext context = run_context(inputs, options, colmap, paths);
  const PhotoSetFacts facts = photo_set_facts(inputs.images, options.camera_mode);
  result.plan = plan_sfm(facts, options);
  result.matcher = result.plan.matcher;
  result.cameras_planned = planned_cameras(result.plan);
  announce_plan(context, colmap, options, result, reporter);

  extract_features(colmap, context, options, paths, reporter, result);
  check_position_priors(facts, options, paths, reporter, result);
  for (const ColmapStep& step : matching_steps(context, result.plan, options)) {
    run_timed(colmap, step, reporter, result);
  }
  const fs::path model_dir = adjust_principal_point(
      colmap, map_photos(colmap, context, options, inputs, paths, reporter, result), options, paths, reporter, result);
  // Undistortion into the workspace the later stages read.
  write_folder_atomically(paths.undistorted, [&](const fs::path& tmp) {
    undistort_with_colmap(colmap, paths.images, model_dir, tmp, result.images_registered, reporter, result);
    const UndistortedWorkspace undistorted = load_undistorted_workspace(tmp);  // the consumers' own check
    if (!inputs.mask_folder.empty()) {
      write_undistorted_masks(read_colmap_model(model_dir), undistorted, inputs.mask_folder, reporter, result);
    }
  });
  result.undistorted = paths.undistorted;
  result.total_seconds = seconds_since(started);
  return result;
}

namespace {

// "principal point: camera 1 (3072x2304, 10 photos) 23.5 px off centre;
// 2 cameras: centre kept: fewer photos than ...": the estimated cameras one
// by one, the others counted by reason.
std::string principal_point_text(const SfmResult& r) {
  std::ostringstream text;
  text.precision(3);
  text << "principal point:";
  std::vector<std::pair<std::string, int>> kept;  // reason, cameras
  for (const auto& c : r.principal_points) {
    if (c.estimated) {
      text << " camera " << c.camera_id << " (" << c.width << "x" << c.height << ", " << c.images
           << (c.images == 1 ? " photo" : " photos") << ") " << c.offset_px << " px off centre;";
      continue;
    }
    auto same = std::find_if(kept.begin(), kept.end(), [&](const auto& k) { return k.first == c.reason; });
    if (same == kept.end()) {
      kept.emplace_back(c.reason, 1);
    } else {
      ++same->second;
    }
  }
  for (const auto& [reason, cameras] : kept)
    text << " " << cameras << (cameras == 1 ? " camera: " : " cameras: ") << reason << ";";
  std::string out = text.str();
  out.pop_back();  // the last ';'
  return out;
}

}  // namespace

std::vector<std::string> sfm_summary_lines(const SfmResult& r) {
  std::vector<std::string> lines;
  for (const VideoClipSummary& clip : r.videos) lines.push_back(describe_selection(clip));
  lines.push_back(
      format_message("registered ", r.images_registered, " of ", r.images_given, " photos (",
                     static_cast<int>(std::lround(100.0 * r.registered_fraction)), "%)",
                     r.skipped.empty() ? std::string() : format_message(", ", r.skipped.size(), " files skipped")));
  if (r.masked_photos > 0) {
    lines.push_back(format_message(r.masked_photos, " photos masked; ", r.masks_undistorted,
                                   " masks undistorted for mvs and texture"));
  }
  if (!r.coverage_warning.empty()) lines.push_back("WARNING: " + r.coverage_warning);
  if (!r.unregistered.empty()) lines.push_back("not registered: " + list_names(r.unregistered));
  std::ostringstream figures;
  figures.precision(3);
  figures << r.points << " 3D points, mean reprojection error " << r.mean_reprojection_error_px
          << " px, mean track length " << r.mean_track_length;
  lines.push_back(figures.str());
  if (!r.principal_points.empty()) lines.push_back(principal_point_text(r));
  if (!r.plan.matcher.empty()) {
    lines.push_back(format_message(r.plan.matcher, " matching (", r.plan.matcher_reason, "), ", r.plan.max_num_features,
                                   " SIFT features per photo"));
    for (const ExtractionRun& run : r.plan.extractions) {
      lines.push_back(format_message("  ", run.description, ": ",
                                     run.single_camera ? "one camera" : "one camera per photo", ", SIFT at most ",
                                     run.sift_max_image_size, " px", run.sift_upsample ? " (and 2x)" : ""));
    }
  }
  if (!r.step_seconds.empty()) lines.push_back(step_times_text(r));
  lines.push_back("undistorted workspace: " + r.undistorted.string());
  return lines;
}

}  // namespace hos::sfm
