// Small SVG plots for the run report, written by hos (no plotting library):
// the page stays self-contained and works offline.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/histogram.h"

namespace hos::pipeline {

struct PlotLabels {
  std::string title;    // above the plot
  std::string x_label;  // below the x axis
};

// Histograms over the same bins as grouped bars, one colour per series,
// with a legend when there is more than one (e.g. seam jumps before and
// after leveling). Each bar's tooltip is its count. Every series must have
// as many bins as the first.
std::string svg_histograms(const std::vector<std::pair<std::string, Histogram>>& series, const PlotLabels& labels);
// One histogram.
std::string svg_histogram(const Histogram& h, const PlotLabels& labels);

// One bar per item (e.g. depth-map coverage per view), heights over
// [0, y_max]; each bar's tooltip is "name: value".
std::string svg_bar_chart(const std::vector<std::pair<std::string, double>>& items,
                          double y_max,
                          const PlotLabels& labels);

// values[i] at x = i + 1 as a line on a log10 y axis (e.g. a solver's
// residual per iteration); values <= 0 or not finite are left out.
std::string svg_log_line_plot(const std::vector<double>& values, const PlotLabels& labels);

// Escapes & < > " for HTML text and attributes.
std::string html_escape(const std::string& text);

}  // namespace hos::pipeline
