// One plot of the run report as data: what a stage's outputs say (read by
// the stage's entry in pipeline/stages.h), drawn as SVG by the report
// (pipeline/report/report_plots.h).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/histogram.h"

namespace hos::pipeline {

struct StagePlot {
  enum class Kind {
    kHistograms,  // histograms: grouped bars over the same bins, one series or more
    kBars,        // bars: one bar per item, heights over [0, y_max]
    kLogLine,     // values: value i at x = i + 1 on a log10 y axis
  };
  StagePlot(std::string plot_id, std::string plot_title, std::string plot_x_label, Kind plot_kind = Kind::kHistograms)
      : id(std::move(plot_id)), title(std::move(plot_title)), x_label(std::move(plot_x_label)), kind(plot_kind) {}

  std::string id;  // the <div>'s id: "plot-depth-coverage"
  std::string title, x_label;
  std::string y_label;  // with its unit; "" for histograms: "count"
  Kind kind = Kind::kHistograms;
  std::vector<std::pair<std::string, Histogram>> histograms;
  std::vector<std::pair<std::string, double>> bars;
  double y_max = 1.0;
  std::vector<double> values;
  std::vector<int> segment_lengths;  // kLogLine: values split into consecutive runs (a solver's solves), each marked
};

}  // namespace hos::pipeline
