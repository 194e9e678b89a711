#include "pipeline/report/report_plots.h"

#include <algorithm>
#include <fstream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/colmap_io.h"
#include "core/error.h"
#include "core/histogram.h"
#include "core/json_report.h"
#include "pipeline/report/svg_plot.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

constexpr int kMaxTrackLength = 30;

void write_plot(std::ostream& html, const char* id, const std::string& svg) {
  html << "<div id=\"" << id << "\">" << svg << "</div>\n";
}

// A histogram stored under key, or nothing if the report has none.
std::optional<Histogram> histogram_at(const nlohmann::json& report, const char* key) {
  if (!report.contains(key)) return std::nullopt;
  Histogram h = histogram_from_json(report[key]);
  if (h.counts.empty()) return std::nullopt;
  return h;
}

void write_sfm_plots(std::ostream& html, const StagePaths& paths) {
  SparseModel model;
  try {
    model = read_colmap_model(paths.undistorted / "sparse");
  } catch (const Error&) {
    return;
  }
  if (model.points.empty()) return;
  std::vector<double> errors, tracks;
  double max_error = 0.0;
  for (const auto& [id, p] : model.points) {
    errors.push_back(p.error);
    tracks.push_back(double(p.track.size()));
    max_error = std::max(max_error, p.error);
  }
  write_plot(html, "plot-reprojection-error",
             svg_histogram(make_histogram(errors, 30, 0.0, std::max(max_error, 0.5)),
                           {"sfm: reprojection error per 3D point", "mean reprojection error (px)"}));
  // One bin per track length from 2, the longer ones in the last bin.
  write_plot(html, "plot-track-length",
             svg_histogram(make_histogram(tracks, kMaxTrackLength - 1, 2.0, double(kMaxTrackLength + 1)),
                           {"sfm: track length per 3D point",
                            "photos observing the point (last bin: " + std::to_string(kMaxTrackLength) + " or more)"}));
}

void write_mvs_plots(std::ostream& html, const StagePaths& paths) {
  const nlohmann::json report = read_json_or_empty(paths.mvs_report);
  std::vector<std::pair<std::string, double>> coverage;
  for (const auto& view : report.value("per_view", nlohmann::json::array())) {
    if (view.value("skipped", false)) continue;
    coverage.emplace_back(view.value("name", ""), view.value("coverage", 0.0));
  }
  if (!coverage.empty()) {
    write_plot(
        html, "plot-depth-coverage",
        svg_bar_chart(coverage, 1.0, {"mvs: depth-map coverage per view", "view (fraction of pixels with a depth)"}));
  }
  if (const auto confidence = histogram_at(report, "confidence")) {
    write_plot(html, "plot-mvs-confidence",
               svg_histogram(*confidence, {"mvs: confidence of the dense points", "confidence (agreeing views)"}));
  }
}

void write_recon_plots(std::ostream& html, const StagePaths& paths) {
  const nlohmann::json report = read_json_or_empty(paths.recon_report);
  const auto residuals = report.value("residual_history", std::vector<double>{});
  if (residuals.empty()) return;
  write_plot(html, "plot-solver-residual",
             svg_log_line_plot(residuals, {"recon: solver residual per iteration",
                                           "CG iteration (all solves in turn); relative residual"}));
}

void write_texture_plots(std::ostream& html, const StagePaths& paths) {
  const nlohmann::json report = read_json_or_empty(paths.texture_report);
  if (const auto views = histogram_at(report, "views_per_face")) {
    write_plot(html, "plot-views-per-face",
               svg_histogram(*views, {"texture: photos seeing each face", "photos (after the visibility test)"}));
  }
  const auto before = histogram_at(report, "seam_jumps_before");
  const auto after = histogram_at(report, "seam_jumps_after");
  if (before && after && before->counts.size() == after->counts.size()) {
    write_plot(html, "plot-seam-jump",
               svg_histograms({{"before leveling", *before}, {"after leveling", *after}},
                              {"texture: colour jump at seam vertices", "RGB distance (8 bit; last bin: larger)"}));
  }
}

}  // namespace

nlohmann::json read_json_or_empty(const fs::path& file) {
  std::ifstream in(file);
  if (!in) return nlohmann::json::object();
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return nlohmann::json::object();
  }
}

void write_stage_plots(std::ostream& html, const StagePaths& paths) {
  for (const auto write : {write_sfm_plots, write_mvs_plots, write_recon_plots, write_texture_plots}) {
    try {
      write(html, paths);
    } catch (const nlohmann::json::exception&) {
      // A report file of another version or a damaged one: its plots are left out, the page is still written.
    }
  }
}

}  // namespace hos::pipeline
