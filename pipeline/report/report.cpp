#include "pipeline/report/report.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "pipeline/report/report_plots.h"
#include "pipeline/report/report_viewer.h"
#include "pipeline/report/svg_plot.h"
#include "pipeline/run_record.h"
#include "pipeline/stage_entries.h"
#include "pipeline/stage_figures.h"
#include "pipeline/stage_paths.h"
#include "pipeline/stages.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

constexpr int kMaxWarningsPerStage = 20;
constexpr int kThumbnailWidth = 160;   // px, as hos-sfm's (sfm/image_inputs.h)
constexpr int kThumbnailQuality = 75;  // JPEG
// The figures of hos-eval's JSON shown first (mesh, render, cameras, sanity).
constexpr const char* kEvalHeadlines[] = {
    "command",   "f_score",   "f_score_threshold", "accuracy.mean",           "completeness.mean", "chamfer",
    "mean_psnr", "mean_ssim", "center_error.mean", "rotation_error_deg.mean", "watertight",        "components"};

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

std::string format_significant(double v) {
  std::ostringstream out;
  out << std::setprecision(5) << v;
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

// A path of the run record as seen from the page's folder (the workspace):
// it reads the same wherever the workspace sits.
std::string relative_to_page(const std::string& path, const StagePaths& paths) {
  std::error_code ec;
  const fs::path page_folder = fs::absolute(paths.root, ec);
  if (ec || !fs::path(path).is_absolute()) return path;
  const fs::path relative = fs::path(path).lexically_relative(page_folder);
  return relative.empty() ? path : relative.generic_string();
}

// 1. Banner: how the run ended.
void write_summary(std::ostream& html, const RunRecord& record, const StagePaths& paths) {
  const Failure failure = find_failure(record);
  html << "<h1>hos run report</h1>\n<p>photos: <code>" << html_escape(relative_to_page(record.photos, paths))
       << "</code><br>result: <code>" << html_escape(relative_to_page(record.output, paths)) << "</code></p>\n";
  if (record.stages.empty()) {
    html << "<p id=\"outcome\">No stage has run in this workspace yet.</p>\n";
    return;
  }
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

// 3. Per stage: state, wall and CPU time, peak memory, key counts, warnings.
void write_stage_table(std::ostream& html, const RunRecord& record, const StagePaths& paths) {
  html << "<h2>Stages</h2>\n<table "
          "id=\"stages\">\n<tr><th>stage</th><th>state</th><th>time</th><th>CPU time</th><th>peak memory</th>"
          "<th>figures</th><th>warnings</th></tr>\n";
  for (const StageSpec& spec : pipeline_stages()) {
    const auto it = record.stages.find(spec.name);
    const bool known = it != record.stages.end();
    const StageRecord stage = known ? it->second : StageRecord{};
    const bool ended = known && stage.state != "running";
    html << "<tr class=\"stage-" << html_escape(known ? stage.state : "not-run") << "\"><td>" << spec.name
         << "</td><td>" << html_escape(known ? stage.state : "not run") << "</td><td>"
         << (ended ? format_fixed(stage.wall_seconds, 1) + " s" : "-") << "</td><td>"
         << (ended && stage.cpu_seconds > 0 ? format_fixed(stage.cpu_seconds, 1) + " s" : "-") << "</td><td>"
         << (ended ? format_fixed(double(stage.peak_memory_bytes) / (1024.0 * 1024.0), 0) + " MB" : "-") << "</td><td>"
         << html_escape(stage.state == "done" ? figures_text(spec.name, stage.figures) : "") << "</td><td>";
    for (const auto& line : log_warnings(paths.log(spec.name))) html << html_escape(line) << "<br>";
    html << "</td></tr>\n";
  }
  html << "</table>\n";
}

// The photo's thumbnail as a data: URI: the one hos-sfm wrote while checking
// the photos; else (a model given with --sparse, or a workspace of an older
// hos) one made here, where the decoder's reduced mode keeps large JPEGs
// cheap; "" if neither can be read.
std::string thumbnail_data_uri(const StagePaths& paths, const std::string& name, const fs::path& photo) {
  std::error_code ec;
  const fs::path written = paths.thumbnails / (name + ".jpg");
  if (fs::is_regular_file(written, ec)) return "data:image/jpeg;base64," + base64(read_bytes(written));
  const cv::Mat reduced = cv::imread(photo.string(), cv::IMREAD_REDUCED_COLOR_4);
  if (reduced.empty()) return "";
  cv::Mat thumbnail = reduced;
  if (reduced.cols > kThumbnailWidth) {
    const int height = std::max(1, reduced.rows * kThumbnailWidth / reduced.cols);
    cv::resize(reduced, thumbnail, cv::Size(kThumbnailWidth, height), 0.0, 0.0, cv::INTER_AREA);
  }
  std::vector<unsigned char> jpeg;
  if (!cv::imencode(".jpg", thumbnail, jpeg, {cv::IMWRITE_JPEG_QUALITY, kThumbnailQuality})) return "";
  return "data:image/jpeg;base64," + base64(std::string(jpeg.begin(), jpeg.end()));
}

// name: the photo's image name, its path relative to the photo folder
// ("DCIM/100APPLE/IMG_1.jpg").
void write_photo(std::ostream& html,
                 const StagePaths& paths,
                 const std::string& name,
                 const fs::path& photo,
                 const std::string& css_class,
                 const std::string& caption) {
  html << "<figure class=\"" << css_class << "\">";
  const std::string uri = thumbnail_data_uri(paths, name, photo);
  if (!uri.empty()) {
    html << "<img width=\"" << kThumbnailWidth << "\" src=\"" << uri << "\" alt=\"" << html_escape(name) << "\">";
  }
  html << "<figcaption>" << html_escape(name) << ": " << html_escape(caption) << "</figcaption></figure>\n";
}

// 6. Photos as embedded thumbnails: the registered ones, the unregistered
// ones, the skipped files with the reason.
void write_photos(std::ostream& html,
                  const RunRecord& record,
                  const StagePaths& paths,
                  const std::optional<sfm::SfmReport>& sfm_report) {
  html << "<h2>Photos</h2>\n";
  // How much of the capture the model uses, and the sfm stage's warning when little.
  if (sfm_report && sfm_report->images_given > 0) {
    html << "<p id=\"coverage\">" << sfm_report->images_registered << " of " << sfm_report->images_given
         << " photos registered (" << std::lround(100 * sfm_report->registered_fraction) << "%)";
    if (!sfm_report->warning.empty()) html << ": <strong>" << html_escape(sfm_report->warning) << "</strong>";
    html << "</p>\n";
  }
  html << "<div id=\"photos\">\n";
  // Image names may hold folders (photos in subfolders).
  const fs::path images = paths.undistorted / "images";
  std::vector<std::string> registered;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(images, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    std::error_code entry_ec;
    if (it->is_regular_file(entry_ec)) registered.push_back(it->path().lexically_relative(images).generic_string());
  }
  std::sort(registered.begin(), registered.end());
  for (const auto& name : registered) write_photo(html, paths, name, images / name, "registered", "registered");
  if (sfm_report) {
    for (const std::string& name : sfm_report->unregistered) {
      write_photo(html, paths, name, fs::path(record.photos) / name, "skipped",
                  "not registered (COLMAP found no pose for it)");
    }
    for (const sfm::SkippedInput& s : sfm_report->skipped) {
      html << "<figure class=\"skipped\"><figcaption>" << html_escape(s.file.string()) << ": skipped ("
           << html_escape(s.reason) << ")</figcaption></figure>\n";
    }
  }
  if (registered.empty() && !sfm_report) html << "<p>The sfm stage has not written its results.</p>\n";
  html << "</div>\n";
}

using EvalRows = std::vector<std::pair<std::string, std::string>>;

// One row per number, flag or text; one level of nesting is spelled
// "accuracy.mean"; lists (per view, per threshold) are left to the file.
void add_eval_rows(EvalRows& rows, const std::string& key, const nlohmann::json& value) {
  if (value.is_object()) {
    for (const auto& [inner, v] : value.items()) {
      if (!v.is_primitive()) continue;
      std::string nested = key;
      nested.append(".").append(inner);
      add_eval_rows(rows, nested, v);
    }
    return;
  }
  if (!value.is_primitive()) return;
  rows.emplace_back(key, value.is_number_float() ? format_significant(value.get<double>())
                         : value.is_string()     ? value.get<std::string>()
                                                 : value.dump());
}

void write_eval_table(std::ostream& html, const EvalRows& rows) {
  html << "<table>\n";
  for (const auto& [key, text] : rows) {
    html << "<tr><td>" << html_escape(key) << "</td><td>" << html_escape(text) << "</td></tr>\n";
  }
  html << "</table>\n";
}

// 5. hos-eval results saved as WS/eval/*.json (docs/eval.md): per file the
// headline figures (kEvalHeadlines, in that order), then all of them folded.
void write_eval_results(std::ostream& html, const StagePaths& paths) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(paths.eval, ec)) {
    if (entry.path().extension() == ".json") files.push_back(entry.path());
  }
  if (files.empty()) return;
  std::sort(files.begin(), files.end());
  html << "<h2>Evaluation</h2>\n<div id=\"eval\">\n";
  for (const fs::path& file : files) {
    const nlohmann::json result = read_json_or_empty(file);
    EvalRows all, headlines;
    for (const auto& [key, value] : result.items()) add_eval_rows(all, key, value);
    for (const char* key : kEvalHeadlines) {
      const auto row = std::find_if(all.begin(), all.end(), [&](const auto& r) { return r.first == key; });
      if (row != all.end()) headlines.push_back(*row);
    }
    html << "<div class=\"eval\"><h3>eval/" << html_escape(file.filename().string()) << "</h3>\n";
    if (result.empty()) html << "<p>not a hos-eval JSON file</p>\n";
    write_eval_table(html, headlines);
    html << "<details><summary>all figures</summary>\n";
    write_eval_table(html, all);
    html << "</details></div>\n";
  }
  html << "</div>\n";
}

// 7. The resolved config and the logs.
void write_config_and_logs(std::ostream& html, const StagePaths& paths) {
  std::error_code ec;
  html << "<h2>Configuration</h2>\n<details id=\"config\"><summary>config.yaml</summary><pre>"
       << html_escape(read_bytes(paths.config)) << "</pre></details>\n";
  html << "<p>Logs: ";
  for (const StageSpec& spec : pipeline_stages()) {
    if (fs::exists(paths.log(spec.name), ec)) {
      html << "<a href=\"logs/" << spec.name << ".log\">" << spec.name << "</a> ";
    }
  }
  html << "</p>\n";
}

constexpr const char* kStyle = R"(<style>
body { font-family: sans-serif; margin: 1em clamp(0.5em, 2vw, 2em); max-width: none; }
table { border-collapse: collapse; } td, th { border: 1px solid #ccc; padding: 0.3em 0.6em; text-align: left; }
#stages { display: block; overflow-x: auto; max-width: 100%; }
pre { overflow-x: auto; }
.ok { color: #1a7f37; } .failed { color: #b42318; font-weight: bold; }
tr.stage-failed, tr.stage-interrupted { background: #fde8e8; }
#photos figure { display: inline-block; margin: 0.3em; font-size: 0.8em; }
figure.skipped { color: #b42318; }
#photos img { display: block; }
div.eval { display: inline-block; margin: 0 1em 1em 0; vertical-align: top; } div.eval h3 { margin: 0.3em 0; }
#plots { display: grid; grid-template-columns: repeat(auto-fill, minmax(min(100%, 26em), 1fr)); gap: 1em; }
svg.plot { display: block; width: 100%; height: auto; } #stage-time { max-width: 40em; margin-top: 1em; }
</style>)";

}  // namespace

std::string run_report_html(const fs::path& workspace, const ReportOptions& options) {
  const StagePaths paths(workspace);
  std::error_code ec;
  // hos-pipeline writes config.yaml before the first stage and run.json as
  // it starts one: a workspace with only the first has run nothing yet.
  if (!fs::is_regular_file(paths.run_record, ec) && !fs::is_regular_file(paths.config, ec)) {
    throw InputError(workspace.string(), "has neither run.json nor config.yaml: not a hos-pipeline workspace");
  }
  const RunRecord record = load_run_record(paths.run_record);
  const std::optional<sfm::SfmReport> sfm_report = written_sfm_report(paths);
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head><meta charset=\"utf-8\">\n"
          "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>hos run report</title>\n"
       << kStyle << "\n</head>\n<body>\n";
  write_summary(html, record, paths);
  html << model_viewer_html(paths, options.viewer_script);  // 2. the model
  write_stage_table(html, record, paths);
  if (const std::string time = stage_time_svg(record); !time.empty()) {
    html << "<div id=\"stage-time\">" << time << "</div>\n";  // where the time went, beside the table
  }
  html << "<h2>Plots</h2>\n<div id=\"plots\">\n";
  write_stage_plots(html, paths);  // 4. plots (pipeline/report/report_plots.h)
  html << "</div>\n";
  write_eval_results(html, paths);
  write_photos(html, record, paths, sfm_report);
  write_config_and_logs(html, paths);
  html << "</body>\n</html>\n";
  return html.str();
}

fs::path write_run_report(const fs::path& workspace, const ReportOptions& options) {
  const std::string html = run_report_html(workspace, options);
  fs::path file = StagePaths(workspace).root / "report.html";
  write_atomically(file, [&](const fs::path& tmp) {
    std::ofstream out(tmp);
    out << html;
    if (!out) throw OutputError(file.string(), "the run report");
  });
  return file;
}

}  // namespace hos::pipeline
