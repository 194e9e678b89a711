// Small SVG plots for the run report, written by hos (no plotting library):
// the page stays self-contained and works offline.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace hos::pipeline {

struct Histogram {
  std::string title;    // above the plot
  std::string x_label;  // below the x axis
  double lo = 0.0;      // left edge of the first bin
  double hi = 1.0;      // right edge of the last bin
  std::vector<std::int64_t> counts;
};

// Bins values into `bins` equal bins over [lo, hi]; values outside are
// clamped into the end bins so that nothing is silently dropped.
Histogram make_histogram(const std::vector<double>& values, int bins, double lo, double hi);

// The histogram as an inline <svg> element with class "plot".
std::string svg_histogram(const Histogram& h);

// Escapes & < > " for HTML text and attributes.
std::string html_escape(const std::string& text);

}  // namespace hos::pipeline
