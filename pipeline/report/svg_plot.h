// Small SVG plots for the run report, written by hos (no plotting library):
// the page stays self-contained and works offline. Each plot has its title,
// both axes' labels, a few ticks with gridlines, and scales with the width
// of its container (viewBox, no fixed size).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/histogram.h"

namespace hos::pipeline {

struct PlotLabels {
  std::string title;    // above the plot
  std::string x_label;  // below the x axis, with its unit: "mean reprojection error (px)"
  std::string y_label;  // along the y axis; "" for histograms: "count"
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
// segment_lengths (optional) splits the values into consecutive runs (e.g.
// the iterations of each linear solve): each run starts at a dashed
// vertical line of class "segment-marker".
std::string svg_log_line_plot(const std::vector<double>& values,
                              const PlotLabels& labels,
                              const std::vector<int>& segment_lengths = {});

// Horizontal bars, one group per row (e.g. a stage) with one bar per
// series (e.g. wall and CPU time), over [0, largest value]; each bar's
// tooltip is "row, series: value". Every series has one value per row.
std::string svg_horizontal_bars(const std::vector<std::string>& rows,
                                const std::vector<std::pair<std::string, std::vector<double>>>& series,
                                const PlotLabels& labels);

// Tick positions over [lo, hi]: steps of 1, 2 or 5 times a power of ten,
// about `target` of them, none
// finer than min_step (1 for counts).
std::vector<double> axis_ticks(double lo, double hi, int target = 5, double min_step = 0.0);

// Escapes & < > " for HTML text and attributes.
std::string html_escape(const std::string& text);

}  // namespace hos::pipeline
