// The texture stage's entry in the stage table: hos-texture picks a photo
// per face and writes the textured model; on a cluster the per-view data are
// chunks of the views and the atlas joins them.
#include <algorithm>
#include <optional>
#include <sstream>

#include "core/error.h"
#include "pipeline/stage_entries.h"
#include "pipeline/stage_figures.h"
#include "refine/refine_options.h"
#include "texture/texture_options.h"
#include "texture/texture_report.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

// Measured speeds (docs/benchmarks-texture.md, 1 M faces, 50 views of
// 1.23 MP, 2 cores): visibility 18.83 s wall, at most 0.75 CPU s per view;
// each of the photo's pixels and the faces is taken to cost all of it alone,
// an upper bound. The rest, 43.7 s wall, at most 1.75e-6 CPU s per face and
// view.
constexpr double kTextureVisibilityCpuSecondsPerView = 0.75;
constexpr double kTextureMeasuredMp = 1.23;
constexpr double kTextureMeasuredFaces = 1e6;
constexpr double kTextureAtlasCpuSecondsPerFaceView = 1.75e-6;

StageSplit split() {
  StageSplit split;
  split.part_name = "views";
  split.join_name = "atlas";
  split.part_arguments = [](const StagePaths& p, const std::string& views) {
    return std::vector<std::string>{
        "--workspace", p.undistorted.string(), "--mesh", p.refined_mesh.string(), "--views", views,
        "--view-data", p.view_data.string()};
  };
  split.join_arguments = [](const StagePaths& p) {
    return std::vector<std::string>{
        "--workspace",      p.undistorted.string(),    "--mesh",   p.refined_mesh.string(),
        "--from-view-data", p.view_data.string(),      "--output", p.textured_model.string(),
        "--report",         p.texture_report.string(), "--geo",    p.sfm_report.string()};
  };
  split.tasks_option = "texture_tasks";
  split.parts_text = "view data";
  return split;
}

// The faces texture works on: its decimation bound, else refine's face
// budget; 0 when neither bounds them (refine off, no decimation).
double texture_faces(const PipelineConfig& config) {
  const auto* texture = stage_options<texture::TextureOptions>(config, "texture");
  if (texture && texture->max_faces > 0) return texture->max_faces;
  const auto* refine = stage_options<refine::RefineOptions>(config, "refine");
  return refine && refine->enabled ? refine->max_faces : 0.0;
}

double job_cpu_seconds(StageJob job, const PipelineConfig& config, const RunBounds& bounds, double chunk) {
  if (bounds.photo_megapixels <= 0) return 0;
  const double faces = texture_faces(config);
  if (faces <= 0) return 0;
  if (job == StageJob::kPart) {
    return chunk * kTextureVisibilityCpuSecondsPerView *
           (bounds.photo_megapixels / kTextureMeasuredMp + faces / kTextureMeasuredFaces);
  }
  if (job == StageJob::kJoin) return faces * std::max(bounds.views, 1) * kTextureAtlasCpuSecondsPerFaceView;
  return 0;
}

void read_figures(const StagePaths& paths, nlohmann::ordered_json& f) {
  // The model's figures also where its report is missing or damaged.
  std::optional<texture::TextureReport> report;
  try {
    report = texture::read_texture_report(paths.texture_report);
  } catch (const InputError&) {
  }
  if (report) f["unseen_faces"] = report->unseen_faces;
  const GlbFigures g = read_glb_figures(paths.textured_model);
  f["bytes"] = g.bytes;
  f["vertices"] = g.vertices;
  f["triangles"] = g.triangles;
  nlohmann::ordered_json sizes = nlohmann::ordered_json::array();
  for (const auto& [w, h] : g.texture_sizes) sizes.push_back(std::to_string(w) + "x" + std::to_string(h));
  f["textures"] = sizes;
  // How the model is placed: "units: metres from GPS (...)" or why the units are arbitrary.
  if (report && !report->placement.units_text.empty()) f["units"] = report->placement.units_text;
}

std::string figures_line(const nlohmann::ordered_json& f) {
  std::ostringstream text;
  text << figure_text(f, "triangles") << " triangles";
  if (f.contains("unseen_faces") && f["unseen_faces"].get<std::int64_t>() > 0) {
    text << ", " << figure_text(f, "unseen_faces") << " faces seen by no photo";
  }
  if (f.contains("textures") && !f["textures"].empty()) {
    text << ", texture";
    for (const auto& s : f["textures"]) text << " " << s.get<std::string>();
  }
  if (f.contains("units")) text << "; " << f["units"].get<std::string>();
  return text.str();
}

// Photos per face and the colour jumps at seams before and after leveling,
// from its report.
std::vector<StagePlot> plots(const StagePaths& paths) {
  const auto written = report_if_written(paths.texture_report, texture::read_texture_report);
  if (!written) return {};
  const texture::TextureReport& report = *written;
  std::vector<StagePlot> plots;
  if (!report.views_per_face.counts.empty()) {
    StagePlot plot{"plot-views-per-face", "texture: photos seeing each face", "photos (after the visibility test)"};
    plot.histograms = {{"", report.views_per_face}};
    plots.push_back(plot);
  }
  const Histogram &before = report.seam_jumps_before, &after = report.seam_jumps_after;
  if (!before.counts.empty() && before.counts.size() == after.counts.size()) {
    StagePlot plot{"plot-seam-jump", "texture: colour jump at seam vertices", "RGB distance (8 bit; last bin: larger)"};
    plot.histograms = {{"before leveling", before}, {"after leveling", after}};
    plots.push_back(plot);
  }
  return plots;
}

}  // namespace

StageSpec texture_stage() {
  StageSpec s;
  s.name = "texture";
  s.executable = "hos-texture";
  s.arguments = [](const DriverOptions&, const StagePaths& p) {
    return std::vector<std::string>{"--workspace", p.undistorted.string(),    "--mesh",   p.refined_mesh.string(),
                                    "--output",    p.textured_model.string(), "--report", p.texture_report.string(),
                                    "--geo",       p.sfm_report.string()};
  };
  s.inputs = [](Fingerprint& f, const DriverOptions&, const PipelineConfig&, const StagePaths& p) {
    f.add_file_contents(p.refined_mesh);
    add_undistorted_workspace(f, p);
    f.add_file_contents(p.sfm_report);  // the photos' GPS (--geo)
  };
  s.output_exists = [](const StagePaths& p) { return fs::exists(p.textured_model); };
  s.make_config = typed_config<texture::TextureOptions>("texture");
  s.split = split();
  // Atlas images (about half the photos) and the mesh.
  s.disk_bytes = [](const fs::path&, const StagePaths& p) {
    return size_of(p.refined_mesh) + size_of(p.undistorted / "images") / 2 + kScratchBytes;
  };
  s.job_memory_mb = [](StageJob, const PipelineConfig&, int) { return 0; };
  s.job_cpu_seconds = job_cpu_seconds;
  s.read_figures = read_figures;
  s.figures_text = figures_line;
  s.plots = plots;
  return s;
}

}  // namespace hos::pipeline
