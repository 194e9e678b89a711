#include "pipeline/report/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

namespace hos::pipeline {
namespace {

constexpr int kWidth = 480, kHeight = 250;
constexpr int kLeft = 70, kRight = 14, kTop = 26, kBottom = 46;
constexpr double kPlotWidth = kWidth - kLeft - kRight, kPlotHeight = kHeight - kTop - kBottom;
constexpr const char* kColours[] = {"#4a7ab7", "#e08a2c", "#3a9a5b", "#9a4ab7"};
constexpr const char* kGrid = "#e4e4e4";

std::string number(double v) {
  // Whole numbers in full (counts: "20000", not "2e+04").
  if (std::abs(v) < 1e9 && v == std::round(v)) return std::to_string(static_cast<long long>(v));
  std::ostringstream out;
  out.precision(3);
  out << (std::abs(v) < 1e-12 ? 0.0 : v);  // no "1e-17" at a tick meant to be 0
  return out.str();
}

const char* colour(std::size_t series) { return kColours[series % std::size(kColours)]; }

// A tick: where it sits along its axis (in SVG units) and its text.
struct Tick {
  double at;
  std::string text;
};

// Ticks at axis_ticks(lo, hi) mapped linearly onto [from, to].
std::vector<Tick> linear_ticks(double lo, double hi, double from, double to, double min_step = 0.0) {
  std::vector<Tick> ticks;
  if (!(hi > lo)) return ticks;
  for (double v : axis_ticks(lo, hi, 5, min_step))
    ticks.push_back({from + (to - from) * (v - lo) / (hi - lo), number(v)});
  return ticks;
}

void open_svg(std::ostream& svg, const PlotLabels& labels, int height = kHeight) {
  svg << "<svg class=\"plot\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " << kWidth << " " << height
      << "\" preserveAspectRatio=\"xMidYMid meet\" role=\"img\" aria-label=\"" << html_escape(labels.title)
      << "\" font-family=\"sans-serif\">\n";
  svg << "<text class=\"title\" x=\"" << kWidth / 2 << "\" y=\"17\" text-anchor=\"middle\" font-size=\"13\">"
      << html_escape(labels.title) << "</text>\n";
}

// Gridlines and tick labels of the y axis (horizontal lines) and the x axis
// (vertical lines), drawn first so that the data lies on top.
void write_grid(std::ostream& svg, const std::vector<Tick>& x_ticks, const std::vector<Tick>& y_ticks, double bottom) {
  for (const Tick& t : y_ticks) {
    svg << "<line class=\"grid\" x1=\"" << kLeft << "\" y1=\"" << t.at << "\" x2=\"" << kLeft + kPlotWidth << "\" y2=\""
        << t.at << "\" stroke=\"" << kGrid << "\"/><text class=\"y-tick\" x=\"" << kLeft - 5 << "\" y=\"" << t.at + 4
        << "\" text-anchor=\"end\" font-size=\"11\">" << html_escape(t.text) << "</text>\n";
  }
  for (const Tick& t : x_ticks) {
    svg << "<line class=\"grid\" x1=\"" << t.at << "\" y1=\"" << kTop << "\" x2=\"" << t.at << "\" y2=\"" << bottom
        << "\" stroke=\"" << kGrid << "\"/><text class=\"x-tick\" x=\"" << t.at << "\" y=\"" << bottom + 14
        << "\" text-anchor=\"middle\" font-size=\"11\">" << html_escape(t.text) << "</text>\n";
  }
}

void close_svg(std::ostream& svg, const PlotLabels& labels, double bottom, int height = kHeight) {
  svg << "<line x1=\"" << kLeft << "\" y1=\"" << bottom << "\" x2=\"" << kLeft + kPlotWidth << "\" y2=\"" << bottom
      << "\" stroke=\"#333\"/>\n";
  svg << "<line x1=\"" << kLeft << "\" y1=\"" << kTop << "\" x2=\"" << kLeft << "\" y2=\"" << bottom
      << "\" stroke=\"#333\"/>\n";
  svg << "<text class=\"x-label\" x=\"" << kLeft + kPlotWidth / 2 << "\" y=\"" << height - 8
      << "\" text-anchor=\"middle\" font-size=\"12\">" << html_escape(labels.x_label) << "</text>\n";
  const double middle = kTop + (bottom - kTop) / 2;
  svg << "<text class=\"y-label\" x=\"14\" y=\"" << middle << "\" transform=\"rotate(-90 14 " << middle
      << ")\" text-anchor=\"middle\" font-size=\"12\">" << html_escape(labels.y_label) << "</text>\n";
  svg << "</svg>\n";
}

// A bar from the x axis up to `fraction` of the plot's height.
void write_bar(std::ostream& svg, double x, double width, double fraction, const char* fill, const std::string& tip) {
  const double height = kPlotHeight * std::clamp(fraction, 0.0, 1.0);
  svg << "<rect x=\"" << x << "\" y=\"" << kTop + kPlotHeight - height << "\" width=\"" << std::max(width, 0.5)
      << "\" height=\"" << height << "\" fill=\"" << fill << "\"><title>" << html_escape(tip) << "</title></rect>\n";
}

void write_legend(std::ostream& svg, const std::vector<std::string>& names) {
  if (names.size() < 2) return;
  for (std::size_t s = 0; s < names.size(); ++s) {
    const double y = kTop + 6 + 14.0 * double(s);
    svg << "<rect x=\"" << kWidth - kRight - 100 << "\" y=\"" << y << "\" width=\"10\" height=\"10\" fill=\""
        << colour(s) << "\"/><text x=\"" << kWidth - kRight - 86 << "\" y=\"" << y + 9 << "\" font-size=\"11\">"
        << html_escape(names[s]) << "</text>\n";
  }
}

PlotLabels with_default_y(PlotLabels labels, const char* y_label) {
  if (labels.y_label.empty()) labels.y_label = y_label;
  return labels;
}

}  // namespace

std::vector<double> axis_ticks(double lo, double hi, int target, double min_step) {
  std::vector<double> ticks;
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo) || target < 1) return ticks;
  const double rough = (hi - lo) / target;
  const double decade = std::pow(10.0, std::floor(std::log10(rough)));
  double step = decade;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * decade;
    if (step >= rough) break;
  }
  step = std::max(step, min_step);
  const double tolerance = 1e-9 * step;
  for (double k = std::ceil((lo - tolerance) / step); k * step <= hi + tolerance; k += 1.0) ticks.push_back(k * step);
  return ticks;
}

std::string svg_histograms(const std::vector<std::pair<std::string, Histogram>>& series, const PlotLabels& labels) {
  std::ostringstream svg;
  open_svg(svg, labels);
  const std::size_t bins = series.empty() ? 0 : series.front().second.counts.size();
  std::int64_t top = 1;
  std::vector<std::string> names;
  for (const auto& [name, h] : series) {
    names.push_back(name);
    if (!h.counts.empty()) top = std::max(top, *std::max_element(h.counts.begin(), h.counts.end()));
  }
  const Histogram empty;
  const Histogram& first = series.empty() ? empty : series.front().second;
  // Bins of one integer each (make_count_histogram) are ticked at whole counts.
  const bool counts = first.bin_width() == 1.0 && std::floor(first.lo) + 0.5 == first.lo;
  const double bottom = kTop + kPlotHeight;
  write_grid(svg, linear_ticks(first.lo, first.hi, kLeft, kLeft + kPlotWidth, counts ? 1.0 : 0.0),
             linear_ticks(0.0, double(top), bottom, kTop, 1.0), bottom);
  const double bin_width = kPlotWidth / double(std::max<std::size_t>(bins, 1));
  const double bar_width = (bin_width - 1.0) / double(std::max<std::size_t>(series.size(), 1));
  for (std::size_t s = 0; s < series.size(); ++s) {
    const Histogram& h = series[s].second;
    for (std::size_t i = 0; i < std::min(bins, h.counts.size()); ++i) {
      write_bar(svg, kLeft + bin_width * double(i) + bar_width * double(s), bar_width,
                double(h.counts[i]) / double(top), colour(s), std::to_string(h.counts[i]));
    }
  }
  write_legend(svg, names);
  close_svg(svg, with_default_y(labels, "count"), bottom);
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
  const double bottom = kTop + kPlotHeight;
  // Item i (from 1) is ticked at its bar's centre.
  std::vector<Tick> x_ticks;
  if (!items.empty()) {
    for (double v : axis_ticks(1.0, double(std::max<std::size_t>(items.size(), 2)), 5, 1.0)) {
      if (v <= double(items.size())) x_ticks.push_back({kLeft + bar_width * (v - 0.5), number(v)});
    }
  }
  write_grid(svg, x_ticks, linear_ticks(0.0, top, bottom, kTop), bottom);
  for (std::size_t i = 0; i < items.size(); ++i) {
    write_bar(svg, kLeft + bar_width * double(i), bar_width - 1.0, items[i].second / top, colour(0),
              items[i].first + ": " + number(items[i].second));
  }
  close_svg(svg, with_default_y(labels, "value"), bottom);
  return svg.str();
}

std::string svg_log_line_plot(const std::vector<double>& values,
                              const PlotLabels& labels,
                              const std::vector<int>& segment_lengths) {
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (double v : values) {
    if (std::isfinite(v) && v > 0.0) {
      lo = std::min(lo, std::log10(v));
      hi = std::max(hi, std::log10(v));
    }
  }
  if (lo > hi) lo = hi = 0.0;
  // Whole decades, so that the ticks read as powers of ten.
  lo = std::floor(lo);
  hi = std::max(std::ceil(hi), lo + 1.0);
  const double bottom = kTop + kPlotHeight;
  const auto y_of = [&](double log_value) { return kTop + kPlotHeight * (hi - log_value) / (hi - lo); };
  const double step = kPlotWidth / double(std::max<std::size_t>(values.size(), 2) - 1);
  const auto x_of = [&](double index) { return kLeft + step * index; };  // index from 0
  std::vector<Tick> y_ticks, x_ticks;
  for (double d : axis_ticks(lo, hi, 5, 1.0)) y_ticks.push_back({y_of(d), "1e" + number(d)});
  if (!values.empty()) {
    for (double v : axis_ticks(1.0, double(std::max<std::size_t>(values.size(), 2)), 5, 1.0)) {
      if (v <= double(values.size())) x_ticks.push_back({x_of(v - 1.0), number(v)});
    }
  }
  std::ostringstream svg;
  open_svg(svg, labels);
  write_grid(svg, x_ticks, y_ticks, bottom);
  // Each run starts half a step before its first value (at the plot's left edge for the first).
  std::size_t start = 0;
  for (std::size_t k = 0; k < segment_lengths.size(); ++k) {
    const double x = start == 0 ? double(kLeft) : x_of(double(start) - 0.5);
    svg << "<line class=\"segment-marker\" x1=\"" << x << "\" y1=\"" << kTop << "\" x2=\"" << x << "\" y2=\"" << bottom
        << "\" stroke=\"#888\" stroke-dasharray=\"4 3\"><title>" << k + 1 << ": " << segment_lengths[k]
        << " iterations</title></line>\n";
    start += std::size_t(std::max(segment_lengths[k], 0));
  }
  svg << "<polyline fill=\"none\" stroke=\"" << colour(0) << "\" stroke-width=\"1.5\" points=\"";
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i]) || values[i] <= 0.0) continue;
    svg << x_of(double(i)) << "," << y_of(std::log10(values[i])) << " ";
  }
  svg << "\"/>\n";
  close_svg(svg, with_default_y(labels, "value (log scale)"), bottom);
  return svg.str();
}

std::string svg_horizontal_bars(const std::vector<std::string>& rows,
                                const std::vector<std::pair<std::string, std::vector<double>>>& series,
                                const PlotLabels& labels) {
  constexpr double kBarHeight = 9.0, kRowGap = 8.0;
  const double row_height = kBarHeight * double(std::max<std::size_t>(series.size(), 1)) + kRowGap;
  // The rows start below the legend (write_legend: 14 units per series).
  const double first_row = kTop + 4 + (series.size() > 1 ? 14.0 * double(series.size()) : 0.0);
  const double bottom = first_row + row_height * double(rows.size());
  const int height = int(std::ceil(bottom)) + kBottom;
  double top = 0.0;
  std::vector<std::string> names;
  for (const auto& [name, values] : series) {
    names.push_back(name);
    for (double v : values) {
      if (std::isfinite(v)) top = std::max(top, v);
    }
  }
  if (!(top > 0.0)) top = 1.0;
  std::ostringstream svg;
  open_svg(svg, labels, height);
  const std::vector<double> tick_values = axis_ticks(0.0, top, 5);
  top = std::max(top, tick_values.empty() ? top : tick_values.back());  // the last tick inside the plot
  write_grid(svg, linear_ticks(0.0, top, kLeft, kLeft + kPlotWidth), {}, bottom);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const double y = first_row + row_height * double(r);
    svg << "<text class=\"row-label\" x=\"" << kLeft - 5 << "\" y=\"" << y + row_height / 2
        << "\" text-anchor=\"end\" font-size=\"11\">" << html_escape(rows[r]) << "</text>\n";
    for (std::size_t s = 0; s < series.size(); ++s) {
      const double v = r < series[s].second.size() && std::isfinite(series[s].second[r]) ? series[s].second[r] : 0.0;
      svg << "<rect x=\"" << kLeft << "\" y=\"" << y + kBarHeight * double(s) << "\" width=\""
          << kPlotWidth * std::clamp(v / top, 0.0, 1.0) << "\" height=\"" << kBarHeight - 1 << "\" fill=\"" << colour(s)
          << "\"><title>" << html_escape(rows[r] + ", " + series[s].first + ": " + number(v)) << "</title></rect>\n";
    }
  }
  write_legend(svg, names);
  close_svg(svg, labels, bottom, height);
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
