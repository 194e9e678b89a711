// The run report's plots, drawn from the files the stages leave in the
// workspace (the sfm model, WS/<stage>/report.json); each plot only where its
// data is there, in a <div id="plot-NAME">:
//   sfm      plot-reprojection-error, plot-track-length
//   mvs      plot-depth-coverage, plot-mvs-confidence
//   recon    plot-solver-residual
//   texture  plot-views-per-face, plot-seam-jump
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>

#include "pipeline/stage_paths.h"

namespace hos::pipeline {

// The JSON in file, or an empty object if it is missing or not JSON (a stage
// that did not finish has written no report).
nlohmann::json read_json_or_empty(const std::filesystem::path& file);

// Writes every plot whose data is in the workspace.
void write_stage_plots(std::ostream& html, const StagePaths& paths);

}  // namespace hos::pipeline
