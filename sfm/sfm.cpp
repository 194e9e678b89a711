#include "sfm/sfm.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "core/atomic_file.h"
#include "core/colmap_io.h"
#include "core/error.h"
#include "core/sparse_model.h"
#include "core/undistorted_workspace.h"
#include "sfm/colmap_runner.h"

namespace hos::sfm {
namespace fs = std::filesystem;
namespace {

constexpr int kExhaustiveBlockSize = 50;  // COLMAP's default block size
constexpr std::size_t kMaxListed = 20;    // names listed in messages

std::string list_names(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < kMaxListed; ++i) out += (i ? ", " : "") + names[i];
  if (names.size() > kMaxListed) out += format_message(" and ", names.size() - kMaxListed, " more");
  return out;
}

bool has_model_files(const fs::path& dir) {
  return fs::exists(dir / "cameras.bin") || fs::exists(dir / "cameras.txt");
}

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
                                "); the end of its output (full log in the stage log):" +
                                format_tail(step.last_lines));
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

void undistort_with_colmap(const ColmapInfo& colmap, const fs::path& images, const fs::path& model,
                           const fs::path& output, std::int64_t num_images, Reporter& reporter,
                           SfmResult& result) {
  ColmapStep step{"image_undistorter",
                  {"--image_path", images.string(), "--input_path", model.string(), "--output_path",
                   output.string(), "--output_type", "COLMAP"},
                  "undistorting images",
                  num_images};
  const ColmapStepResult run = run_colmap_step(colmap, step, reporter);
  require_ok(run, "image_undistorter");
  result.step_seconds.emplace_back("image_undistorter", run.seconds);
  remove_colmap_extras(output);
}

void clear_previous_run(const SfmPaths& paths) {
  std::error_code ec;
  for (const auto& p : {paths.report, paths.undistorted, paths.sparse, paths.database, paths.images}) {
    fs::remove_all(p, ec);
  }
  fs::remove(paths.database.string() + "-shm", ec);
  fs::remove(paths.database.string() + "-wal", ec);
}

// Existing-model input: check it, then undistort it (or copy it when it is
// already undistorted) into the workspace.
SfmResult import_existing_model(const SfmInput& input, const SfmOptions& options, const SfmPaths& paths,
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
    throw InputError(model_dir.string(), format_message("has only ", result.images_registered,
                                                        " registered images (need ",
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
      undistort_with_colmap(colmap, input.images, model_dir, tmp,
                            static_cast<std::int64_t>(model.images.size()), reporter, result);
    }
    load_undistorted_workspace(tmp);  // the consumers' own check
  });
  result.undistorted = paths.undistorted;
  return result;
}

}  // namespace

SfmPaths sfm_paths(const fs::path& workspace) {
  SfmPaths p;
  p.root = workspace / "sfm";
  p.images = p.root / "images";
  p.database = p.root / "database.db";
  p.sparse = p.root / "sparse";
  p.undistorted = p.root / "undistorted";
  p.report = p.root / "report.json";
  return p;
}

SfmResult run_sfm(const SfmInput& input, const SfmOptions& options, Reporter& reporter) {
  options.validate();
  const SfmPaths paths = sfm_paths(input.workspace);
  std::error_code ec;
  fs::create_directories(paths.root, ec);
  if (ec) throw OutputError(paths.root.string(), "cannot create the workspace folder: " + ec.message());
  clear_previous_run(paths);

  if (!input.existing_model.empty()) return import_existing_model(input, options, paths, reporter);

  // Inputs first: a bad photo folder is reported even where COLMAP is missing.
  SfmResult result;
  const ImageInputs inputs = prepare_images(input.images, paths.images, options, reporter);
  result.skipped = inputs.skipped;
  result.images_given = static_cast<int>(inputs.images.size());
  const auto num_images = static_cast<std::int64_t>(inputs.images.size());

  const ColmapInfo colmap = locate_colmap(options.colmap);
  result.colmap_version = colmap.version;
  const bool gpu = options.use_gpu == "yes" || (options.use_gpu == "auto" && colmap.cuda);
  const std::string gpu_flag = gpu ? "1" : "0";
  const std::string threads = std::to_string(options.num_threads);
  const std::string seed = std::to_string(options.random_seed);
  result.single_camera = options.camera_mode == "single" ||
                         (options.camera_mode == "auto" && inputs.same_camera());
  reporter.info(format_message(num_images, " photos, ", result.single_camera ? "one shared camera" : "one camera per photo",
                               " (", options.camera_model, "), COLMAP ", colmap.version,
                               gpu ? " with GPU" : " on the CPU"));

  // 1. Features.
  const ColmapStep extract{"feature_extractor",
                           {"--random_seed", seed, "--database_path", paths.database.string(), "--image_path",
                            paths.images.string(), "--ImageReader.camera_model", options.camera_model,
                            "--ImageReader.single_camera", result.single_camera ? "1" : "0",
                            "--SiftExtraction.use_gpu", gpu_flag, "--SiftExtraction.num_threads", threads,
                            "--SiftExtraction.max_num_features", std::to_string(options.max_num_features),
                            "--SiftExtraction.peak_threshold", format_message(options.sift_peak_threshold)},
                           "extracting features",
                           num_images};
  const ColmapStepResult extracted = run_colmap_step(colmap, extract, reporter);
  require_ok(extracted, "feature_extractor");
  result.step_seconds.emplace_back("feature_extractor", extracted.seconds);

  // 2. Matching: exhaustive is best for unordered photo sets; ordered video
  // frames only overlap with their neighbours.
  const bool sequential = options.matcher == "sequential" ||
                          (options.matcher == "auto" && num_images > options.exhaustive_max_images);
  result.matcher = sequential ? "sequential" : "exhaustive";
  ColmapStep match;
  match.args = {"--random_seed", seed, "--database_path", paths.database.string(), "--SiftMatching.use_gpu",
                gpu_flag, "--SiftMatching.num_threads", threads};
  if (sequential) {
    match.command = "sequential_matcher";
    match.args.insert(match.args.end(), {"--SequentialMatching.overlap", std::to_string(options.sequential_overlap)});
    match.total = num_images;
  } else {
    match.command = "exhaustive_matcher";
    const std::int64_t blocks = (num_images + kExhaustiveBlockSize - 1) / kExhaustiveBlockSize;
    match.args.insert(match.args.end(), {"--ExhaustiveMatching.block_size", std::to_string(kExhaustiveBlockSize)});
    match.total = blocks * blocks;
  }
  match.title = "matching (" + result.matcher + ")";
  const ColmapStepResult matched = run_colmap_step(colmap, match, reporter);
  require_ok(matched, match.command);
  result.step_seconds.emplace_back(match.command, matched.seconds);

  // 3. Mapping. Small secondary models are kept (min_model_size 3) so they
  // can be reported.
  fs::create_directories(paths.sparse);
  const ColmapStep map{"mapper",
                       {"--random_seed", seed, "--database_path", paths.database.string(), "--image_path",
                        paths.images.string(), "--output_path", paths.sparse.string(), "--Mapper.num_threads",
                        threads, "--Mapper.min_model_size", "3", "--Mapper.abs_pose_min_num_inliers",
                        std::to_string(options.min_pose_inliers)},
                       "mapping",
                       num_images};
  const ColmapStepResult mapped = run_colmap_step(colmap, map, reporter);
  result.step_seconds.emplace_back("mapper", mapped.seconds);
  const auto models = numbered_models(paths.sparse);
  if (models.empty()) {
    throw StageError("sfm", format_message(
                                "COLMAP could not register the photos (no model from ", num_images,
                                " photos): they may not overlap enough or lack texture. "
                                "Photos of one object need 60-80% overlap between neighbours.",
                                mapped.exit_code != 0 ? " COLMAP mapper output ends with:" + format_tail(mapped.last_lines)
                                                      : std::string()));
  }
  require_ok(mapped, "mapper");

  // 4. Read every model; the largest is the result.
  SparseModel best;
  fs::path best_dir;
  for (const auto& [index, dir] : models) {
    SparseModel model = read_colmap_model(dir);
    result.models.push_back({index, static_cast<int>(model.images.size()), static_cast<std::int64_t>(model.points.size())});
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
      if (m.index != result.used_model) others += format_message(others.empty() ? "" : ", ", "model ", m.index, " (", m.images, " images)");
    }
    reporter.warn(format_message("COLMAP split the photos into ", result.models.size(), " models; using model ",
                                 result.used_model, " (", result.images_registered, " images), ignoring ", others));
  }
  if (result.images_registered < options.min_registered_images) {
    throw StageError("sfm", format_message("only ", result.images_registered, " of ", num_images,
                                           " photos registered (need ", options.min_registered_images,
                                           "): the photos may not overlap enough. Not registered: ",
                                           list_names(result.unregistered)));
  }

  // 5. Undistortion into the workspace the later stages read.
  write_folder_atomically(paths.undistorted, [&](const fs::path& tmp) {
    undistort_with_colmap(colmap, paths.images, best_dir, tmp, result.images_registered, reporter, result);
    load_undistorted_workspace(tmp);  // the consumers' own check
  });
  result.undistorted = paths.undistorted;
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
  j["models"] = nlohmann::json::array();
  for (const auto& m : r.models) j["models"].push_back({{"index", m.index}, {"images", m.images}, {"points", m.points}});
  j["used_model"] = r.used_model;
  j["matcher"] = r.matcher;
  j["single_camera"] = r.single_camera;
  j["colmap_version"] = r.colmap_version;
  nlohmann::ordered_json steps = nlohmann::ordered_json::object();
  for (const auto& [name, seconds] : r.step_seconds) steps[name] = seconds;
  j["step_seconds"] = steps;
  write_atomically(file, [&](const fs::path& tmp) {
    std::ofstream out(tmp);
    out << j.dump(2) << "\n";
    if (!out) throw OutputError(file.string(), "cannot write");
  });
}

std::vector<std::string> sfm_summary_lines(const SfmResult& r) {
  std::vector<std::string> lines;
  lines.push_back(format_message("registered ", r.images_registered, " of ", r.images_given, " photos",
                                 r.skipped.empty() ? std::string() : format_message(" (", r.skipped.size(), " files skipped)")));
  if (!r.unregistered.empty()) lines.push_back("not registered: " + list_names(r.unregistered));
  std::ostringstream figures;
  figures.precision(3);
  figures << r.points << " 3D points, mean reprojection error " << r.mean_reprojection_error_px
          << " px, mean track length " << r.mean_track_length;
  lines.push_back(figures.str());
  if (!r.step_seconds.empty()) {
    std::ostringstream times;
    times.precision(3);
    times << "COLMAP times:";
    for (const auto& [name, seconds] : r.step_seconds) times << " " << name << " " << seconds << " s;";
    lines.push_back(times.str());
  }
  lines.push_back("undistorted workspace: " + r.undistorted.string());
  return lines;
}

}  // namespace hos::sfm
