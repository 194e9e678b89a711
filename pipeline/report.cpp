#include "pipeline/report.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "core/atomic_file.h"
#include "core/colmap_io.h"
#include "core/error.h"
#include "core/ply_io.h"
#include "pipeline/report_viewer.h"
#include "pipeline/run_record.h"
#include "pipeline/stage_figures.h"
#include "pipeline/stage_paths.h"
#include "pipeline/stages.h"
#include "pipeline/svg_plot.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

constexpr int kMaxWarningsPerStage = 20;
constexpr int kMaxTrackLength = 30;

std::string read_text_file(const fs::path& file) {
  std::ifstream in(file);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The warning and error lines a stage wrote to its log ("[mvs] warning: ...").
std::vector<std::string> log_warnings(const fs::path& log) {
  std::vector<std::string> lines;
  std::ifstream in(log);
  for (std::string line; std::getline(in, line) && int(lines.size()) < kMaxWarningsPerStage;) {
    if (line.find("] warning: ") != std::string::npos || line.find("] error: ") != std::string::npos) {
      lines.push_back(line);
    }
  }
  return lines;
}

std::string format_fixed(double v, int digits) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << v;
  return out.str();
}

// The first stage that did not finish, with how it ended; empty if none.
struct Failure {
  std::string stage, state;
  int exit_code = 0;
};
Failure find_failure(const RunRecord& record) {
  for (const StageSpec& spec : pipeline_stages()) {
    const auto it = record.stages.find(spec.name);
    if (it == record.stages.end()) continue;
    const std::string& state = it->second.state;
    if (state == "failed" || state == "interrupted" || state == "running" || state == "submitted") {
      return {spec.name, state, it->second.exit_code};
    }
  }
  return {};
}

// 1. Banner: how the run ended.
void write_summary(std::ostream& html, const RunRecord& record) {
  const Failure failure = find_failure(record);
  html << "<h1>hos run report</h1>\n<p>photos: <code>" << html_escape(record.photos) << "</code><br>result: <code>"
       << html_escape(record.output) << "</code></p>\n";
  if (failure.stage.empty()) {
    html << "<p class=\"ok\" id=\"outcome\">The run finished.</p>\n";
    return;
  }
  const std::string how = failure.state == "failed" ? "failed (exit code " + std::to_string(failure.exit_code) + ")"
                          : failure.state == "interrupted" ? "was interrupted"
                          : failure.state == "submitted"   ? "was submitted to Slurm and had not finished"
                                                           : "did not finish (the driver stopped)";
  html << "<p class=\"failed\" id=\"outcome\">The run stopped at stage <b id=\"failed-stage\">" << failure.stage
       << "</b>: it " << how << ". See <a href=\"logs/" << failure.stage << ".log\">logs/" << failure.stage
       << ".log</a>.</p>\n";
}

// 3. Per stage: state, time, peak memory, key counts, warnings.
void write_stage_table(std::ostream& html, const RunRecord& record, const StagePaths& paths) {
  html << "<h2>Stages</h2>\n<table "
          "id=\"stages\">\n<tr><th>stage</th><th>state</th><th>time</th><th>peak memory</th>"
          "<th>figures</th><th>warnings</th></tr>\n";
  for (const StageSpec& spec : pipeline_stages()) {
    const auto it = record.stages.find(spec.name);
    const bool known = it != record.stages.end();
    const StageRecord stage = known ? it->second : StageRecord{};
    const bool ended = known && stage.state != "running";
    html << "<tr class=\"stage-" << html_escape(known ? stage.state : "not-run") << "\"><td>" << spec.name
         << "</td><td>" << html_escape(known ? stage.state : "not run") << "</td><td>"
         << (ended ? format_fixed(stage.wall_seconds, 1) + " s" : "-") << "</td><td>"
         << (ended ? format_fixed(double(stage.peak_memory_bytes) / (1024.0 * 1024.0), 0) + " MB" : "-") << "</td><td>"
         << html_escape(stage.state == "done" ? figures_text(spec.name, stage.figures) : "") << "</td><td>";
    for (const auto& line : log_warnings(paths.log(spec.name))) html << html_escape(line) << "<br>";
    html << "</td></tr>\n";
  }
  html << "</table>\n";
}

// 4. Photos: the registered ones as thumbnails, the others with the reason.
void write_photos(std::ostream& html, const StagePaths& paths, const nlohmann::json& sfm_report) {
  html << "<h2>Photos</h2>\n<div id=\"photos\">\n";
  const fs::path images = paths.undistorted / "images";
  std::vector<std::string> registered;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(images, ec)) registered.push_back(entry.path().filename().string());
  std::sort(registered.begin(), registered.end());
  for (const auto& name : registered) {
    // Relative to the page: it stays valid when the workspace is moved.
    html << "<figure class=\"registered\"><img loading=\"lazy\" width=\"160\" "
            "src=\"sfm/undistorted/images/"
         << html_escape(name) << "\" alt=\"" << html_escape(name) << "\"><figcaption>" << html_escape(name)
         << ": registered</figcaption></figure>\n";
  }
  for (const auto& name : sfm_report.value("unregistered", std::vector<std::string>{})) {
    html << "<figure class=\"skipped\"><figcaption>" << html_escape(name)
         << ": not registered (COLMAP found no pose for it)</figcaption></figure>\n";
  }
  for (const auto& s : sfm_report.value("skipped", nlohmann::json::array())) {
    html << "<figure class=\"skipped\"><figcaption>" << html_escape(s.value("file", "")) << ": skipped ("
         << html_escape(s.value("reason", "")) << ")</figcaption></figure>\n";
  }
  if (registered.empty() && sfm_report.empty()) html << "<p>The sfm stage has not written its results.</p>\n";
  html << "</div>\n";
}

// 5. Plots, each only where its data is in the workspace.
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
  Histogram error_plot = make_histogram(errors, 30, 0.0, std::max(max_error, 0.5));
  error_plot.title = "sfm: reprojection error per 3D point";
  error_plot.x_label = "mean reprojection error (px)";
  // One bin per track length from 2, the longer ones in the last bin.
  Histogram track_plot = make_histogram(tracks, kMaxTrackLength - 1, 2.0, double(kMaxTrackLength + 1));
  track_plot.title = "sfm: track length per 3D point";
  track_plot.x_label = "photos observing the point (last bin: " + std::to_string(kMaxTrackLength) + " or more)";
  html << "<div id=\"plot-reprojection-error\">" << svg_histogram(error_plot) << "</div>\n";
  html << "<div id=\"plot-track-length\">" << svg_histogram(track_plot) << "</div>\n";
}

void write_mvs_plots(std::ostream& html, const StagePaths& paths) {
  PointCloud cloud;
  try {
    cloud = read_point_cloud_ply(paths.points);
  } catch (const Error&) {
    return;
  }
  if (!cloud.has_confidence()) return;
  const float top = *std::max_element(cloud.confidence.begin(), cloud.confidence.end());
  const std::vector<double> values(cloud.confidence.begin(), cloud.confidence.end());
  // Confidence counts agreeing views (mvs/fusion.h): one bin per count.
  const int bins = std::clamp(int(std::ceil(top)), 1, 40);
  Histogram plot = make_histogram(values, bins, 0.5, double(bins) + 0.5);
  plot.title = "mvs: confidence of the dense points";
  plot.x_label = "confidence (agreeing views)";
  html << "<div id=\"plot-mvs-confidence\">" << svg_histogram(plot) << "</div>\n";
}

// 6. The resolved config and the logs.
void write_config_and_logs(std::ostream& html, const StagePaths& paths) {
  std::error_code ec;
  html << "<h2>Configuration</h2>\n<details id=\"config\"><summary>config.yaml</summary><pre>"
       << html_escape(read_text_file(paths.config)) << "</pre></details>\n";
  html << "<p>Logs: ";
  for (const StageSpec& spec : pipeline_stages()) {
    if (fs::exists(paths.log(spec.name), ec)) {
      html << "<a href=\"logs/" << spec.name << ".log\">" << spec.name << "</a> ";
    }
  }
  html << "</p>\n";
}

nlohmann::json load_sfm_report(const fs::path& file) {
  std::ifstream in(file);
  if (!in) return nlohmann::json::object();
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return nlohmann::json::object();
  }
}

constexpr const char* kStyle = R"(<style>
body { font-family: sans-serif; margin: 2em; max-width: 75em; }
table { border-collapse: collapse; } td, th { border: 1px solid #ccc; padding: 0.3em 0.6em; text-align: left; }
.ok { color: #1a7f37; } .failed { color: #b42318; font-weight: bold; }
tr.stage-failed, tr.stage-interrupted { background: #fde8e8; }
#photos figure { display: inline-block; margin: 0.3em; font-size: 0.8em; }
figure.skipped { color: #b42318; }
div[id^=plot-] { display: inline-block; margin: 0.5em; }
</style>)";

}  // namespace

std::string run_report_html(const fs::path& workspace, const ReportOptions& options) {
  const StagePaths paths(workspace);
  std::error_code ec;
  if (!fs::is_regular_file(paths.run_record, ec)) {
    throw InputError(workspace.string(), "has no run.json: not a hos-pipeline workspace");
  }
  const RunRecord record = load_run_record(paths.run_record);
  const nlohmann::json sfm_report = load_sfm_report(paths.sfm_report);
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head><meta charset=\"utf-8\"><title>hos run "
          "report</title>\n"
       << kStyle << "\n</head>\n<body>\n";
  write_summary(html, record);
  html << model_viewer_html(paths, options.viewer_script);  // 2. the model
  write_stage_table(html, record, paths);
  write_photos(html, paths, sfm_report);
  html << "<h2>Plots</h2>\n";
  write_sfm_plots(html, paths);
  write_mvs_plots(html, paths);
  write_config_and_logs(html, paths);
  html << "</body>\n</html>\n";
  return html.str();
}

fs::path write_run_report(const fs::path& workspace, const ReportOptions& options) {
  const std::string html = run_report_html(workspace, options);
  const fs::path file = StagePaths(workspace).root / "report.html";
  write_atomically(file, [&](const fs::path& tmp) {
    std::ofstream out(tmp);
    out << html;
    if (!out) throw OutputError(file.string(), "cannot write");
  });
  return file;
}

}  // namespace hos::pipeline
