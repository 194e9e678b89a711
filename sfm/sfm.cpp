#include "sfm/sfm.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "core/atomic_file.h"
#include "core/colmap_io.h"
#include "core/error.h"
#include "core/sparse_model.h"
#include "core/stopwatch.h"
#include "core/undistorted_workspace.h"
#include "sfm/colmap_runner.h"
#include "sfm/colmap_steps.h"

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
  result.step_seconds.emplace_back("image_undistorter", run.seconds);
  remove_colmap_extras(output);
}

void clear_previous_run(const SfmPaths& paths) {
  std::error_code ec;
  for (const auto& p : {paths.report, paths.undistorted, paths.sparse, paths.database, paths.vocab_tree, paths.images,
                        paths.thumbnails}) {
    fs::remove_all(p, ec);
  }
  fs::remove(paths.database.string() + "-shm", ec);
  fs::remove(paths.database.string() + "-wal", ec);
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
  for (const auto& [id, image] : model.images) {
    const fs::path file = input.images / image.name;
    if (!fs::exists(file)) throw InputError(file.string(), "image of the sparse model is missing");
  }
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
    load_undistorted_workspace(tmp);  // the consumers' own check
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
  ImageInputs inputs = prepare_images(input.images, paths.images, options, reporter, paths.thumbnails);
  result.step_seconds.emplace_back("prepare_images", seconds_since(started));
  result.skipped = inputs.skipped;
  result.images_given = static_cast<int>(inputs.images.size());
  return inputs;
}

PhotoSetFacts photo_set_facts(const ImageInputs& inputs) {
  PhotoSetFacts facts;
  facts.photos = static_cast<int>(inputs.images.size());
  for (const StagedImage& image : inputs.images) {
    facts.photos_with_gps += image.gps ? 1 : 0;
    facts.longest_side_px = std::max({facts.longest_side_px, image.width, image.height});
  }
  return facts;
}

ColmapRunContext run_context(const ImageInputs& inputs,
                             const SfmOptions& options,
                             const ColmapInfo& colmap,
                             const SfmPaths& paths,
                             SfmResult& result) {
  ColmapRunContext context;
  context.database = paths.database;
  context.images = paths.images;
  context.sparse = paths.sparse;
  context.vocab_tree = paths.vocab_tree;
  context.gpu = options.use_gpu == "yes" || (options.use_gpu == "auto" && colmap.cuda);
  context.single_camera = options.camera_mode == "single" || (options.camera_mode == "auto" && inputs.same_camera());
  context.num_images = static_cast<std::int64_t>(inputs.images.size());
  result.single_camera = context.single_camera;
  return context;
}

void announce_plan(const ColmapRunContext& context,
                   const ColmapInfo& colmap,
                   const SfmOptions& options,
                   const SfmResult& result,
                   Reporter& reporter) {
  const SfmPlan& plan = result.plan;
  reporter.info(format_message(
      context.num_images, " photos, ", context.single_camera ? "one shared camera" : "one camera per photo", " (",
      options.camera_model, "), COLMAP ", colmap.version, context.gpu ? " with GPU" : " on the CPU"));
  reporter.info(format_message("SIFT at most ", plan.sift_max_image_size, " px", plan.sift_upsample ? " (and 2x)" : "",
                               ", ", plan.max_num_features, " features per photo, ", plan.max_num_matches,
                               " matches per pair; ", plan.matcher, " matching (", plan.matcher_reason, ")"));
}

// Runs one COLMAP command, fails the stage on an error exit, keeps its time.
void run_timed(const ColmapInfo& colmap, const ColmapStep& step, Reporter& reporter, SfmResult& result) {
  const ColmapStepResult run = run_colmap_step(colmap, step, reporter);
  require_ok(run, step.command);
  result.step_seconds.emplace_back(step.command, run.seconds);
}

// Reads every model the mapper wrote and picks the largest; returns its folder.
fs::path select_largest_model(const std::vector<std::pair<int, fs::path>>& models,
                              const ImageInputs& inputs,
                              Reporter& reporter,
                              SfmResult& result) {
  SparseModel best;
  fs::path best_dir;
  for (const auto& [index, dir] : models) {
    SparseModel model = read_colmap_model(dir);
    result.models.push_back(
        {index, static_cast<int>(model.images.size()), static_cast<std::int64_t>(model.points.size())});
    if (best_dir.empty() || model.images.size() > best.images.size()) {
      best = std::move(model);
      best_dir = dir;
      result.used_model = index;
    }
  }
  fill_model_figures(best, result);
  for (const auto& image : inputs.images) {
    if (!best.find_image(image.name)) result.unregistered.push_back(image.name);
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

// The mapper, then the largest model; fails the stage when too few photos
// registered. Returns the chosen model's folder.
fs::path map_photos(const ColmapInfo& colmap,
                    const ColmapRunContext& context,
                    const SfmOptions& options,
                    const ImageInputs& inputs,
                    Reporter& reporter,
                    SfmResult& result) {
  fs::create_directories(context.sparse);
  const ColmapStepResult mapped = run_colmap_step(colmap, mapping_step(context, options), reporter);
  result.step_seconds.emplace_back("mapper", mapped.seconds);
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
  if (result.images_registered < options.min_registered_images) {
    throw StageError("sfm", format_message("only ", result.images_registered, " of ", context.num_images,
                                           " photos registered (need ", options.min_registered_images,
                                           "): the photos may not overlap enough. Not registered: ",
                                           list_names(result.unregistered)));
  }
  return best_dir;
}

// The final bundle adjustment that also estimates the principal point,
// whose model is kept when the estimate stays within
// options.principal_point_max_offset of the image centre (an estimate
// farther away means the photos did not constrain it). Returns the folder
// of the model to use.
fs::path adjust_principal_point(const ColmapInfo& colmap,
                                const fs::path& model_dir,
                                const SfmOptions& options,
                                const SfmPaths& paths,
                                Reporter& reporter,
                                SfmResult& result) {
  if (options.principal_point_max_offset <= 0) return model_dir;
  fs::path adjusted_dir = paths.sparse / "principal_point";
  fs::remove_all(adjusted_dir);
  fs::create_directories(adjusted_dir);
  const ColmapStepResult run = run_colmap_step(colmap, principal_point_step(model_dir, adjusted_dir), reporter);
  result.step_seconds.emplace_back("bundle_adjuster", run.seconds);
  if (run.exit_code != 0) {
    reporter.warn("sfm: the principal point's bundle adjustment failed; the image centre is kept" +
                  format_tail(run.last_lines));
    return model_dir;
  }
  const SparseModel adjusted = read_colmap_model(adjusted_dir);
  const PrincipalPointOffset offset = largest_principal_point_offset(adjusted);
  if (offset.fraction > options.principal_point_max_offset) {
    reporter.warn(format_message("sfm: the principal point was estimated ", offset.pixels,
                                 " px from the image centre, more than sfm.principal_point_max_offset (",
                                 options.principal_point_max_offset,
                                 " of the longer side): the photos do not constrain it; the image centre is kept"));
    return model_dir;
  }
  fill_model_figures(adjusted, result);
  result.principal_point_offset_px = offset.pixels;
  result.principal_point_estimated = true;
  return adjusted_dir;
}

}  // namespace

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
  p.thumbnails = p.root / "thumbnails";
  p.database = p.root / "database.db";
  p.vocab_tree = p.root / "vocab_tree.bin";
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
  const ColmapRunContext context = run_context(inputs, options, colmap, paths, result);
  result.plan = plan_sfm(photo_set_facts(inputs), options);
  result.matcher = result.plan.matcher;
  announce_plan(context, colmap, options, result, reporter);

  run_timed(colmap, feature_extraction_step(context, result.plan, options), reporter, result);
  for (const ColmapStep& step : matching_steps(context, result.plan, options)) {
    run_timed(colmap, step, reporter, result);
  }
  const fs::path model_dir = adjust_principal_point(
      colmap, map_photos(colmap, context, options, inputs, reporter, result), options, paths, reporter, result);
  // Undistortion into the workspace the later stages read.
  write_folder_atomically(paths.undistorted, [&](const fs::path& tmp) {
    undistort_with_colmap(colmap, paths.images, model_dir, tmp, result.images_registered, reporter, result);
    load_undistorted_workspace(tmp);  // the consumers' own check
  });
  result.undistorted = paths.undistorted;
  result.total_seconds = seconds_since(started);
  return result;
}

void write_sfm_report(const SfmResult& r, const fs::path& file) {
  nlohmann::ordered_json j;
  j["images_given"] = r.images_given;
  j["images_registered"] = r.images_registered;
  j["unregistered"] = r.unregistered;
  j["skipped"] = nlohmann::json::array();
  for (const auto& s : r.skipped) j["skipped"].push_back({{"file", s.file.string()}, {"reason", s.reason}});
  j["points"] = r.points;
  j["mean_reprojection_error_px"] = r.mean_reprojection_error_px;
  j["mean_track_length"] = r.mean_track_length;
  j["principal_point"] = {{"estimated", r.principal_point_estimated}, {"offset_px", r.principal_point_offset_px}};
  j["models"] = nlohmann::json::array();
  for (const auto& m : r.models)
    j["models"].push_back({{"index", m.index}, {"images", m.images}, {"points", m.points}});
  j["used_model"] = r.used_model;
  j["matcher"] = r.matcher;
  if (!r.plan.matcher.empty()) {
    j["plan"] = {{"matcher", r.plan.matcher},
                 {"matcher_reason", r.plan.matcher_reason},
                 {"max_num_features", r.plan.max_num_features},
                 {"max_num_matches", r.plan.max_num_matches},
                 {"sift_max_image_size", r.plan.sift_max_image_size},
                 {"sift_upsample", r.plan.sift_upsample},
                 {"vocab_tree_words", r.plan.vocab_tree_words}};
  }
  j["single_camera"] = r.single_camera;
  j["colmap_version"] = r.colmap_version;
  nlohmann::ordered_json steps = nlohmann::ordered_json::object();
  for (const auto& [name, seconds] : r.step_seconds) steps[name] = seconds;
  j["step_seconds"] = steps;
  j["total_seconds"] = r.total_seconds;
  write_atomically(file, [&](const fs::path& tmp) {
    std::ofstream out(tmp);
    out << j.dump(2) << "\n";
    if (!out) throw OutputError(file.string(), "cannot write");
  });
}

std::vector<std::string> sfm_summary_lines(const SfmResult& r) {
  std::vector<std::string> lines;
  lines.push_back(
      format_message("registered ", r.images_registered, " of ", r.images_given, " photos",
                     r.skipped.empty() ? std::string() : format_message(" (", r.skipped.size(), " files skipped)")));
  if (!r.unregistered.empty()) lines.push_back("not registered: " + list_names(r.unregistered));
  std::ostringstream figures;
  figures.precision(3);
  figures << r.points << " 3D points, mean reprojection error " << r.mean_reprojection_error_px
          << " px, mean track length " << r.mean_track_length;
  if (r.principal_point_estimated) figures << ", principal point " << r.principal_point_offset_px << " px off centre";
  lines.push_back(figures.str());
  if (!r.plan.matcher.empty()) {
    lines.push_back(format_message(r.plan.matcher, " matching (", r.plan.matcher_reason, "), ", r.plan.max_num_features,
                                   " SIFT features per photo at most ", r.plan.sift_max_image_size, " px"));
  }
  if (!r.step_seconds.empty()) lines.push_back(step_times_text(r));
  lines.push_back("undistorted workspace: " + r.undistorted.string());
  return lines;
}

}  // namespace hos::sfm
