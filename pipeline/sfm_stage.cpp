// The sfm stage's entry in the stage table: hos-sfm registers the photos and
// writes the undistorted workspace every later stage reads.
#include <algorithm>
#include <iomanip>
#include <sstream>

#include "core/colmap_io.h"
#include "core/error.h"
#include "core/json_report.h"
#include "pipeline/output_checks.h"
#include "pipeline/stage_entries.h"
#include "sfm/image_inputs.h"
#include "sfm/sfm_options.h"
#include "sfm/sfm_report.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

// Measured speed, CPU seconds (user + sys) per photo: fountain-P11, 88 CPU s
// for 11 photos of 6.3 MP (docs/benchmarks-sfm.md).
constexpr double kSfmCpuSecondsPerPhoto = 8.0;
// Track lengths from this on share the plot's last bin.
constexpr int kMaxTrackLength = 30;

std::vector<std::string> arguments(const DriverOptions& o, const StagePaths& p) {
  std::vector<std::string> args{"--images", o.photos.string(), "--workspace", p.root.string()};
  if (!o.existing_model.empty()) args.insert(args.end(), {"--sparse", o.existing_model.string()});
  return args;
}

// What hos-sfm reads: the photos (masks beside them among them), not
// sidecars or notes, and the folder of masks given apart.
void inputs(Fingerprint& f, const DriverOptions& o, const PipelineConfig& config, const StagePaths& p) {
  f.add_file_listing(o.photos, sfm::list_photo_files(o.photos, pipeline_files_in_photos(o.photos, o.output, p.root)));
  const auto* sfm = stage_options<sfm::SfmOptions>(config, "sfm");
  std::error_code ec;
  if (sfm && fs::is_directory(sfm->mask_folder(), ec)) f.add_folder_listing(sfm->mask_folder());
  if (!o.existing_model.empty()) f.add_folder_contents(o.existing_model);
}

void read_figures(const StagePaths& paths, nlohmann::ordered_json& f) {
  const sfm::SfmReport r = sfm::read_sfm_report(paths.sfm_report);
  f["images_registered"] = r.images_registered;
  f["images_given"] = r.images_given;
  f["points"] = r.points;
  f["mean_reprojection_error_px"] = r.mean_reprojection_error_px;
  f["mean_track_length"] = r.mean_track_length;
  if (!r.matcher.empty()) f["matcher"] = r.matcher;
  f["step_seconds"] = named_values_json(r.step_seconds);  // in the order the steps ran
}

std::string figures_line(const nlohmann::ordered_json& f) {
  std::ostringstream text;
  text << figure_text(f, "images_registered") << "/" << figure_text(f, "images_given") << " images registered, "
       << figure_text(f, "points") << " points";
  if (f.contains("matcher")) text << ", " << f["matcher"].get<std::string>() << " matching";
  if (f.contains("step_seconds")) {
    // The COLMAP steps' times, so a slow step shows in the summary.
    text << std::fixed << std::setprecision(1);
    for (const auto& [step, seconds] : f["step_seconds"].items())
      text << "; " << step << " " << seconds.get<double>() << " s";
  }
  return text.str();
}

// Reprojection error and track length per 3D point, from the sparse model.
std::vector<StagePlot> plots(const StagePaths& paths) {
  SparseModel model;
  try {
    model = read_colmap_model(paths.undistorted / "sparse");
  } catch (const Error&) {
    return {};
  }
  if (model.points.empty()) return {};
  std::vector<double> errors, tracks;
  double max_error = 0.0;
  for (const auto& [id, p] : model.points) {
    errors.push_back(p.error);
    tracks.push_back(double(p.track.size()));
    max_error = std::max(max_error, p.error);
  }
  StagePlot error{"plot-reprojection-error", "sfm: reprojection error per 3D point", "mean reprojection error (px)"};
  error.histograms = {{"", make_histogram(errors, 30, 0.0, std::max(max_error, 0.5))}};
  // One bin per track length from 2, the longer ones in the last bin.
  StagePlot track{"plot-track-length", "sfm: track length per 3D point",
                  "photos observing the point (last bin: " + std::to_string(kMaxTrackLength) + " or more)"};
  track.histograms = {{"", make_histogram(tracks, kMaxTrackLength - 1, 2.0, double(kMaxTrackLength + 1))}};
  return {error, track};
}

}  // namespace

StageSpec sfm_stage() {
  StageSpec s;
  s.name = "sfm";
  s.executable = "hos-sfm";
  s.arguments = arguments;
  s.inputs = inputs;
  s.output_exists = [](const StagePaths& p) {
    return fs::exists(p.undistorted / "sparse") && fs::exists(p.sfm_report);
  };
  s.make_config = typed_config<sfm::SfmOptions>("sfm");
  // The feature database and the undistorted copies, about the photos' size each.
  s.disk_bytes = [](const fs::path& photos, const StagePaths&) { return 2 * size_of(photos) + kScratchBytes; };
  s.job_memory_mb = [](StageJob, const PipelineConfig&, int) { return 0; };
  s.job_cpu_seconds = [](StageJob, const PipelineConfig&, const RunBounds& bounds, double) {
    return std::max(bounds.views, 1) * kSfmCpuSecondsPerPhoto;
  };
  s.read_figures = read_figures;
  s.figures_text = figures_line;
  s.plots = plots;
  return s;
}

}  // namespace hos::pipeline
