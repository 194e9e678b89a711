// The mvs stage's entry in the stage table: hos-mvs computes a depth map per
// view and fuses them into oriented points; on a cluster the depth maps are
// chunks of the views and fusion joins them.
#include <algorithm>
#include <cmath>

#include "mvs/fusion_store.h"
#include "mvs/mvs_options.h"
#include "mvs/mvs_report.h"
#include "mvs/patch_match.h"
#include "pipeline/stage_entries.h"
#include "pipeline/stage_figures.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

// Measured speed, CPU seconds (user + sys) per view per matched MP:
// fountain-P11 matched in one level at 1024 px, 185 CPU s for 10 views of
// 0.70 MP (docs/benchmarks-mvs.md); the whole run, fusion included.
constexpr double kMvsCpuSecondsPerViewMp = 26.5;

StageSplit split() {
  StageSplit split;
  split.part_name = "depth";
  split.join_name = "fuse";
  split.part_arguments = [](const StagePaths& p, const std::string& views) {
    return std::vector<std::string>{"--workspace", p.undistorted.string(), "--views",
                                    views,         "--depth-maps",         p.depth_maps.string()};
  };
  split.join_arguments = [](const StagePaths& p) {
    return std::vector<std::string>{"--workspace", p.undistorted.string(), "--fuse",   p.depth_maps.string(),
                                    "--output",    p.points.string(),      "--report", p.mvs_report.string()};
  };
  split.tasks_option = "mvs_tasks";
  split.parts_text = "depth maps";
  return split;
}

// The finest level at a 4:3 aspect; a depth chunk holds the reference view
// and its sources (grey float + colour), the planes, costs and the sources'
// coarse priors; fusion what its store holds at most.
int job_memory_mb(StageJob job, const PipelineConfig& config, int views) {
  const auto* mvs = stage_options<mvs::MvsOptions>(config, "mvs");
  if (!mvs || job == StageJob::kWhole) return 0;
  const double pixels = 0.75 * double(mvs->max_image_size) * mvs->max_image_size;
  const double bytes = job == StageJob::kPart
                           ? pixels * (7.0 * (1 + mvs->num_source_views) + mvs::matcher_bytes_per_pixel(*mvs))
                           : mvs::fusion_peak_bytes(*mvs, pixels, views);
  return static_cast<int>(std::ceil(512.0 + 1.5 * bytes / (1024.0 * 1024.0)));
}

double job_cpu_seconds(StageJob job, const PipelineConfig& config, const RunBounds& bounds, double chunk) {
  const auto* mvs = stage_options<mvs::MvsOptions>(config, "mvs");
  if (!mvs || job == StageJob::kWhole) return 0;
  const double views = std::max(bounds.views, 1);
  double fine_mp = megapixels_at(mvs->max_image_size);
  if (bounds.photo_megapixels > 0) fine_mp = std::min(fine_mp, bounds.photo_megapixels);
  if (job == StageJob::kJoin) return views * fine_mp * kMvsCpuSecondsPerViewMp;  // bounded by the whole run
  // With finer levels a chunk also matches its sources' coarse level: up to
  // num_source_views more coarse views per view, at most every view.
  const bool multi_scale = mvs->max_image_size > mvs->coarse_image_size;
  const double coarse_views = multi_scale ? std::min(views - chunk, chunk * mvs->num_source_views) : 0.0;
  const double coarse_mp = std::min(fine_mp, megapixels_at(mvs->coarse_image_size));
  return (chunk * fine_mp + coarse_views * coarse_mp) * kMvsCpuSecondsPerViewMp;
}

// Depth-map coverage per view and the points' confidence, from its report.
std::vector<StagePlot> plots(const StagePaths& paths) {
  const auto written = report_if_written(paths.mvs_report, mvs::read_mvs_report);
  if (!written) return {};
  const mvs::MvsReport& report = *written;
  std::vector<StagePlot> plots;
  StagePlot coverage{"plot-depth-coverage", "mvs: depth-map coverage per view", "view (hover a bar for its name)",
                     StagePlot::Kind::kBars};
  coverage.y_label = "fraction of pixels with a depth";
  for (const mvs::MvsViewReport& view : report.per_view) {
    if (!view.skipped) coverage.bars.emplace_back(view.name, view.coverage);
  }
  if (!coverage.bars.empty()) plots.push_back(coverage);
  if (!report.confidence.counts.empty()) {
    StagePlot plot{"plot-mvs-confidence", "mvs: confidence of the dense points", "confidence (agreeing views)"};
    plot.histograms = {{"", report.confidence}};
    plots.push_back(plot);
  }
  return plots;
}

}  // namespace

StageSpec mvs_stage() {
  StageSpec s;
  s.name = "mvs";
  s.executable = "hos-mvs";
  s.arguments = [](const DriverOptions&, const StagePaths& p) {
    return std::vector<std::string>{"--workspace", p.undistorted.string(), "--output", p.points.string(),
                                    "--report",    p.mvs_report.string()};
  };
  s.inputs = [](Fingerprint& f, const DriverOptions&, const PipelineConfig&, const StagePaths& p) {
    add_undistorted_workspace(f, p);
  };
  s.output_exists = [](const StagePaths& p) { return fs::exists(p.points); };
  s.make_config = typed_config<mvs::MvsOptions>("mvs");
  s.split = split();
  // Dense points: at most about the images' size.
  s.disk_bytes = [](const fs::path&, const StagePaths& p) { return size_of(p.undistorted) + kScratchBytes; };
  s.job_memory_mb = job_memory_mb;
  s.job_cpu_seconds = job_cpu_seconds;
  s.read_figures = [](const StagePaths& p, nlohmann::ordered_json& f) {
    f["points"] = ply_element_counts(p.points)["vertex"];
  };
  s.figures_text = [](const nlohmann::ordered_json& f) { return figure_text(f, "points") + " dense points"; };
  s.plots = plots;
  return s;
}

}  // namespace hos::pipeline
