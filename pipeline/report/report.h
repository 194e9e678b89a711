// The run report WS/report.html: one self-contained page per run, built from
// the workspace alone (run.json, sfm/report.json, the stages' outputs,
// config.yaml, logs), so it can be written after a finished, failed or
// interrupted run and rewritten later with `hos-pipeline --report WS`.
#pragma once

#include <filesystem>
#include <string>

namespace hos::pipeline {

struct ReportOptions {
  // model-viewer's bundle (default_viewer_script in pipeline/report/report_viewer.h);
  // empty or missing: the page links the model instead of showing it.
  std::filesystem::path viewer_script;
};

// The page's HTML. Throws InputError if WS has neither run.json nor
// config.yaml (a workspace where no stage has run yet has only the second).
std::string run_report_html(const std::filesystem::path& workspace, const ReportOptions& options = {});

// Writes WS/report.html atomically and returns its path. Throws InputError
// (as run_report_html), OutputError (cannot write).
std::filesystem::path write_run_report(const std::filesystem::path& workspace, const ReportOptions& options = {});

}  // namespace hos::pipeline
