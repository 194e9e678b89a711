#include "pipeline/report/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

namespace hos::pipeline {
namespace {

constexpr int kWidth = 420, kHeight = 220;
constexpr int kLeft = 56, kRight = 12, kTop = 24, kBottom = 40;
constexpr double kPlotWidth = kWidth - kLeft - kRight, kPlotHeight = kHeight - kTop - kBottom;
constexpr const char* kColours[] = {"#4a7ab7", "#e08a2c", "#3a9a5b", "#9a4ab7"};

std::string number(double v) {
  std::ostringstream out;
  out.precision(3);
  out << v;
  return out.str();
}

const char* colour(std::size_t series) { return kColours[series % std::size(kColours)]; }

// The texts at the ends of the axes: enough to read the shape and the scale.
struct AxisEnds {
  std::string y_top, y_bottom, x_first, x_last;
};

void open_svg(std::ostream& svg, const PlotLabels& labels) {
  svg << "<svg class=\"plot\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << kHeight
      << "\" viewBox=\"0 0 " << kWidth << " " << kHeight << "\" role=\"img\" aria-label=\"" << html_escape(labels.title)
      << "\">\n";
  svg << "<text x=\"" << kWidth / 2 << "\" y=\"16\" text-anchor=\"middle\" font-size=\"13\">"
      << html_escape(labels.title) << "</text>\n";
}

void close_svg(std::ostream& svg, const PlotLabels& labels, const AxisEnds& ends) {
  const double bottom = kTop + kPlotHeight;
  svg << "<line x1=\"" << kLeft << "\" y1=\"" << bottom << "\" x2=\"" << kLeft + kPlotWidth << "\" y2=\"" << bottom
      << "\" stroke=\"#333\"/>\n";
  svg << "<line x1=\"" << kLeft << "\" y1=\"" << kTop << "\" x2=\"" << kLeft << "\" y2=\"" << bottom
      << "\" stroke=\"#333\"/>\n";
  svg << "<text x=\"" << kLeft - 4 << "\" y=\"" << kTop + 10 << "\" text-anchor=\"end\" font-size=\"11\">"
      << html_escape(ends.y_top) << "</text>\n";
  svg << "<text x=\"" << kLeft - 4 << "\" y=\"" << bottom << "\" text-anchor=\"end\" font-size=\"11\">"
      << html_escape(ends.y_bottom) << "</text>\n";
  svg << "<text x=\"" << kLeft << "\" y=\"" << bottom + 14 << "\" font-size=\"11\">" << html_escape(ends.x_first)
      << "</text>\n";
  svg << "<text x=\"" << kLeft + kPlotWidth << "\" y=\"" << bottom + 14 << "\" text-anchor=\"end\" font-size=\"11\">"
      << html_escape(ends.x_last) << "</text>\n";
  svg << "<text x=\"" << kLeft + kPlotWidth / 2 << "\" y=\"" << kHeight - 6
      << "\" text-anchor=\"middle\" font-size=\"11\">" << html_escape(labels.x_label) << "</text>\n";
  svg << "</svg>\n";
}

// A bar from the x axis up to `fraction` of the plot's height.
void write_bar(std::ostream& svg, double x, double width, double fraction, const char* fill, const std::string& tip) {
  const double height = kPlotHeight * std::clamp(fraction, 0.0, 1.0);
  svg << "<rect x=\"" << x << "\" y=\"" << kTop + kPlotHeight - height << "\" width=\"" << std::max(width, 0.5)
      << "\" height=\"" << height << "\" fill=\"" << fill << "\"><title>" << html_escape(tip) << "</title></rect>\n";
}

void write_legend(std::ostream& svg, const std::vector<std::pair<std::string, Histogram>>& series) {
  if (series.size() < 2) return;
  for (std::size_t s = 0; s < series.size(); ++s) {
    const double y = kTop + 6 + 14.0 * double(s);
    svg << "<rect x=\"" << kWidth - kRight - 90 << "\" y=\"" << y << "\" width=\"10\" height=\"10\" fill=\""
        << colour(s) << "\"/><text x=\"" << kWidth - kRight - 76 << "\" y=\"" << y + 9 << "\" font-size=\"11\">"
        << html_escape(series[s].first) << "</text>\n";
  }
}

}  // namespace

std::string svg_histograms(const std::vector<std::pair<std::string, Histogram>>& series, const PlotLabels& labels) {
  std::ostringstream svg;
  open_svg(svg, labels);
  const std::size_t bins = series.empty() ? 0 : series.front().second.counts.size();
  std::int64_t top = 1;
  for (const auto& [name, h] : series) {
    if (!h.counts.empty()) top = std::max(top, *std::max_element(h.counts.begin(), h.counts.end()));
  }
  const double bin_width = kPlotWidth / double(std::max<std::size_t>(bins, 1));
  const double bar_width = (bin_width - 1.0) / double(std::max<std::size_t>(series.size(), 1));
  for (std::size_t s = 0; s < series.size(); ++s) {
    const Histogram& h = series[s].second;
    for (std::size_t i = 0; i < std::min(bins, h.counts.size()); ++i) {
      write_bar(svg, kLeft + bin_width * double(i) + bar_width * double(s), bar_width,
                double(h.counts[i]) / double(top), colour(s), std::to_string(h.counts[i]));
    }
  }
  write_legend(svg, series);
  const Histogram empty;
  const Histogram& first = series.empty() ? empty : series.front().second;
  // Bins of one integer each (make_count_histogram) are named by their centres.
  const double inset = first.bin_width() == 1.0 && std::floor(first.lo) + 0.5 == first.lo ? 0.5 : 0.0;
  close_svg(svg, labels, {std::to_string(top), "0", number(first.lo + inset), number(first.hi - inset)});
  return svg.str();
}

std::string svg_histogram(const Histogram& h, const PlotLabels& labels) { return svg_histograms({{"", h}}, labels); }

std::string svg_bar_chart(const std::vector<std::pair<std::string, double>>& items,
                          double y_max,
                          const PlotLabels& labels) {
  std::ostringstream svg;
  open_svg(svg, labels);
  const double top = y_max > 0.0 ? y_max : 1.0;
  const double bar_width = kPlotWidth / double(std::max<std::size_t>(items.size(), 1));
  for (std::size_t i = 0; i < items.size(); ++i) {
    write_bar(svg, kLeft + bar_width * double(i), bar_width - 1.0, items[i].second / top, colour(0),
              items[i].first + ": " + number(items[i].second));
  }
  close_svg(svg, labels, {number(top), "0", "1", std::to_string(items.size())});
  return svg.str();
}

std::string svg_log_line_plot(const std::vector<double>& values, const PlotLabels& labels) {
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (double v : values) {
    if (std::isfinite(v) && v > 0.0) {
      lo = std::min(lo, std::log10(v));
      hi = std::max(hi, std::log10(v));
    }
  }
  if (lo > hi) lo = hi = 0.0;
  // Whole decades, so that the axis ends read as powers of ten.
  lo = std::floor(lo);
  hi = std::max(std::ceil(hi), lo + 1.0);
  std::ostringstream svg;
  open_svg(svg, labels);
  svg << "<polyline fill=\"none\" stroke=\"" << colour(0) << "\" stroke-width=\"1.5\" points=\"";
  const double step = kPlotWidth / double(std::max<std::size_t>(values.size(), 2) - 1);
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i]) || values[i] <= 0.0) continue;
    const double y = kTop + kPlotHeight * (hi - std::log10(values[i])) / (hi - lo);
    svg << kLeft + step * double(i) << "," << y << " ";
  }
  svg << "\"/>\n";
  close_svg(svg, labels, {"1e" + number(hi), "1e" + number(lo), "1", std::to_string(values.size())});
  return svg.str();
}

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace hos::pipeline
