// The refine stage's entry in the stage table: hos-refine moves the recon
// mesh to where the photos agree.
#include <algorithm>

#include "pipeline/stage_entries.h"
#include "refine/refine_options.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

// Measured speed, CPU seconds (user + sys) per view per photo MP at its
// default face budget: Herz-Jesu-P8, 42.9 CPU s for 8 photos of 6.3 MP,
// 300000 faces (docs/refine.md).
constexpr double kRefineCpuSecondsPerViewMp = 0.85;
constexpr double kRefineMeasuredFaces = 300000.0;

double job_cpu_seconds(StageJob, const PipelineConfig& config, const RunBounds& bounds, double) {
  if (bounds.photo_megapixels <= 0) return 0;
  const auto* refine = stage_options<refine::RefineOptions>(config, "refine");
  if (!refine || !refine->enabled) return 0;
  const double faces_factor = std::max(1.0, refine->max_faces / kRefineMeasuredFaces);
  return std::max(bounds.views, 1) * bounds.photo_megapixels * kRefineCpuSecondsPerViewMp * faces_factor;
}

}  // namespace

StageSpec refine_stage() {
  StageSpec s;
  s.name = "refine";
  s.executable = "hos-refine";
  s.arguments = [](const DriverOptions&, const StagePaths& p) {
    return std::vector<std::string>{"--workspace", p.undistorted.string(), "--mesh", p.mesh.string(),
                                    "--output",    p.refined_mesh.string()};
  };
  s.inputs = [](Fingerprint& f, const DriverOptions&, const PipelineConfig&, const StagePaths& p) {
    f.add_file_contents(p.mesh);
    add_undistorted_workspace(f, p);
  };
  s.output_exists = [](const StagePaths& p) { return fs::exists(p.refined_mesh); };
  s.make_config = typed_config<refine::RefineOptions>("refine");
  // The refined mesh: the recon mesh's vertices moved, its faces split up to
  // the face budget; about the recon mesh's size.
  s.disk_bytes = [](const fs::path&, const StagePaths& p) { return size_of(p.mesh) + kScratchBytes; };
  s.job_memory_mb = [](StageJob, const PipelineConfig&, int) { return 0; };
  s.job_cpu_seconds = job_cpu_seconds;
  s.read_figures = [](const StagePaths& p, nlohmann::ordered_json& f) { add_mesh_figures(p.refined_mesh, f); };
  s.figures_text = mesh_figures_text;
  s.plots = [](const StagePaths&) { return std::vector<StagePlot>{}; };
  return s;
}

}  // namespace hos::pipeline
