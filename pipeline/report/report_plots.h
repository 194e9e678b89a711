// The run report's plots: each stage's plots of the stage table
// (pipeline/stages.h, StageSpec::plots), drawn as SVG, each in a
// <div id="plot-NAME">, only where its data is in the workspace:
//   sfm      plot-reprojection-error, plot-track-length
//   mvs      plot-depth-coverage, plot-mvs-confidence
//   recon    plot-solver-residual (a marker where each solve starts)
//   texture  plot-views-per-face, plot-seam-jump
// The time per stage (stage_time_svg, from run.json) goes beside the
// stage table.
#pragma once

#include <ostream>
#include <string>

#include "pipeline/run_record.h"
#include "pipeline/stage_paths.h"
#include "pipeline/stage_plot.h"

namespace hos::pipeline {

// The plot as SVG.
std::string plot_svg(const StagePlot& plot);

// Wall and CPU time of each stage that ended, as horizontal bars; "" when
// none has.
std::string stage_time_svg(const RunRecord& record);

// Writes every plot whose data is in the workspace.
void write_stage_plots(std::ostream& html, const StagePaths& paths);

}  // namespace hos::pipeline
