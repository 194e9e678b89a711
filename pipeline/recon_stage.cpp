// The recon stage's entry in the stage table: hos-recon reconstructs the
// surface from the dense points; on a cluster recon.tiles makes it one task
// per tile and a join.
#include <cmath>
#include <iomanip>
#include <sstream>

#include "pipeline/stage_entries.h"
#include "recon/recon_options.h"
#include "recon/recon_report.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

// Measured speed at grid 1024: the bunny, 41.3 CPU s (user + sys;
// docs/benchmarks-recon.md); the work grows with the grid's nodes.
constexpr double kReconCpuSecondsAtGrid1024 = 41.3;

// Only recon.tiles fixes the tiles before the points exist; with 0 the plan
// follows the points and the budget, and the one job tiles in turn when it
// must.
StageSplit split() {
  StageSplit split;
  split.part_name = "tiles";
  split.join_name = "join";
  split.part_arguments = [](const StagePaths& p, const std::string& tile) {
    return std::vector<std::string>{"--input", p.points.string(), "--tile", tile, "--tile-dir", p.recon_tiles.string()};
  };
  split.join_arguments = [](const StagePaths& p) {
    return std::vector<std::string>{"--input",  p.points.string(), "--join-tiles", p.recon_tiles.string(),
                                    "--output", p.mesh.string(),   "--report",     p.recon_report.string()};
  };
  split.fixed_parts = [](const PipelineConfig& config) {
    const auto* recon = stage_options<recon::ReconOptions>(config, "recon");
    return recon ? recon->tiles : 0;
  };
  return split;
}

// recon refuses a grid whose estimated peak exceeds its budget, so the
// budget (with room for the process itself) bounds the job. The tiles' count
// is known before the points, their sizes are not: the budget bounds each
// tile task too (hos-recon --tile refuses a tile whose solve's estimate
// exceeds it), and the join, which holds one core at a time, asks for the
// same.
int job_memory_mb(StageJob, const PipelineConfig& config, int) {
  const auto* recon = stage_options<recon::ReconOptions>(config, "recon");
  return recon && recon->max_memory_mb > 0 ? recon->max_memory_mb + 512 : 0;
}

// A tile's grid is cut at the samples' median, not at an even share of the
// nodes, so it may span most of the whole grid: the whole grid's time bounds
// each tile, and the join (blending and meshing, no solve).
double job_cpu_seconds(StageJob, const PipelineConfig& config, const RunBounds&, double) {
  const auto* recon = stage_options<recon::ReconOptions>(config, "recon");
  if (!recon || recon->resolution <= 0) return 0;  // the grid follows the points' density: unknown before
  return kReconCpuSecondsAtGrid1024 * std::pow(recon->resolution / 1024.0, 3);
}

void read_figures(const StagePaths& paths, nlohmann::ordered_json& f) {
  add_mesh_figures(paths.mesh, f);
  const recon::ReconReport report = recon::read_recon_report(paths.recon_report);
  f["debris_pieces_removed"] = report.debris_pieces_removed;
  f["debris_area_removed"] = report.debris_area_removed;
  f["surface_area"] = report.surface_area;
}

std::string figures_line(const nlohmann::ordered_json& f) {
  std::ostringstream text;
  text << mesh_figures_text(f);
  if (f.contains("debris_pieces_removed") && f["debris_pieces_removed"].get<std::int64_t>() > 0) {
    text << "; " << figure_text(f, "debris_pieces_removed") << " debris pieces removed";
    const double removed = f.value("debris_area_removed", 0.0), kept = f.value("surface_area", 0.0);
    if (removed + kept > 0.0)
      text << " (" << std::setprecision(2) << 100.0 * removed / (removed + kept) << "% of the area)";
  }
  return text.str();
}

// The solver's residual per iteration, from its report.
std::vector<StagePlot> plots(const StagePaths& paths) {
  const auto written = report_if_written(paths.recon_report, recon::read_recon_report);
  if (!written) return {};
  const recon::ReconReport& report = *written;
  if (report.residual_history.empty()) return {};
  StagePlot plot{"plot-solver-residual", "recon: solver residual per iteration",
                 "CG iteration (all solves in turn, dashed: a solve starts)", StagePlot::Kind::kLogLine};
  plot.y_label = "relative residual |r| / |b|";
  plot.values = report.residual_history;
  plot.segment_lengths = report.solve_iterations;
  return {plot};
}

}  // namespace

StageSpec recon_stage() {
  StageSpec s;
  s.name = "recon";
  s.executable = "hos-recon";
  s.arguments = [](const DriverOptions&, const StagePaths& p) {
    return std::vector<std::string>{"--input",       p.points.string(), "--output",
                                    p.mesh.string(), "--report",        p.recon_report.string()};
  };
  s.inputs = [](Fingerprint& f, const DriverOptions&, const PipelineConfig&, const StagePaths& p) {
    f.add_file_contents(p.points);
  };
  s.output_exists = [](const StagePaths& p) { return fs::exists(p.mesh); };
  s.make_config = typed_config<recon::ReconOptions>("recon");
  s.split = split();
  // A mesh about the size of the points.
  s.disk_bytes = [](const fs::path&, const StagePaths& p) { return size_of(p.points) + kScratchBytes; };
  s.job_memory_mb = job_memory_mb;
  s.job_cpu_seconds = job_cpu_seconds;
  s.read_figures = read_figures;
  s.figures_text = figures_line;
  s.plots = plots;
  return s;
}

}  // namespace hos::pipeline
