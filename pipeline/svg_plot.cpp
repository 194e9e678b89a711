#include "pipeline/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

namespace hos::pipeline {
namespace {

constexpr int kWidth = 420, kHeight = 220;
constexpr int kLeft = 48, kRight = 12, kTop = 24, kBottom = 40;

std::string number(double v) {
  std::ostringstream out;
  out.precision(3);
  out << v;
  return out.str();
}

}  // namespace

Histogram make_histogram(const std::vector<double>& values, int bins, double lo, double hi) {
  Histogram h;
  h.lo = lo;
  h.hi = hi > lo ? hi : lo + 1.0;
  h.counts.assign(static_cast<std::size_t>(std::max(bins, 1)), 0);
  const double width = (h.hi - h.lo) / double(h.counts.size());
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    const auto bin = static_cast<std::int64_t>(std::floor((v - h.lo) / width));
    h.counts[std::size_t(std::clamp<std::int64_t>(bin, 0, std::int64_t(h.counts.size()) - 1))]++;
  }
  return h;
}

std::string svg_histogram(const Histogram& h) {
  const std::int64_t top = std::max<std::int64_t>(1, *std::max_element(h.counts.begin(), h.counts.end()));
  const double plot_w = kWidth - kLeft - kRight, plot_h = kHeight - kTop - kBottom;
  const double bar_w = plot_w / double(h.counts.size());
  std::ostringstream svg;
  svg << "<svg class=\"plot\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << kHeight
      << "\" viewBox=\"0 0 " << kWidth << " " << kHeight << "\" role=\"img\" aria-label=\"" << html_escape(h.title)
      << "\">\n";
  svg << "<text x=\"" << kWidth / 2 << "\" y=\"16\" text-anchor=\"middle\" font-size=\"13\">" << html_escape(h.title)
      << "</text>\n";
  for (std::size_t i = 0; i < h.counts.size(); ++i) {
    const double bar_h = plot_h * double(h.counts[i]) / double(top);
    svg << "<rect x=\"" << kLeft + bar_w * double(i) << "\" y=\"" << kTop + plot_h - bar_h << "\" width=\""
        << std::max(bar_w - 1.0, 0.5) << "\" height=\"" << bar_h << "\" fill=\"#4a7ab7\"><title>" << h.counts[i]
        << "</title></rect>\n";
  }
  // Axes with their end values: enough to read the shape and the scale.
  svg << "<line x1=\"" << kLeft << "\" y1=\"" << kTop + plot_h << "\" x2=\"" << kLeft + plot_w << "\" y2=\""
      << kTop + plot_h << "\" stroke=\"#333\"/>\n";
  svg << "<line x1=\"" << kLeft << "\" y1=\"" << kTop << "\" x2=\"" << kLeft << "\" y2=\"" << kTop + plot_h
      << "\" stroke=\"#333\"/>\n";
  svg << "<text x=\"" << kLeft - 4 << "\" y=\"" << kTop + 10 << "\" text-anchor=\"end\" font-size=\"11\">" << top
      << "</text>\n";
  svg << "<text x=\"" << kLeft - 4 << "\" y=\"" << kTop + plot_h
      << "\" text-anchor=\"end\" font-size=\"11\">0</text>\n";
  svg << "<text x=\"" << kLeft << "\" y=\"" << kTop + plot_h + 14 << "\" font-size=\"11\">" << number(h.lo)
      << "</text>\n";
  svg << "<text x=\"" << kLeft + plot_w << "\" y=\"" << kTop + plot_h + 14 << "\" text-anchor=\"end\" font-size=\"11\">"
      << number(h.hi) << "</text>\n";
  svg << "<text x=\"" << kLeft + plot_w / 2 << "\" y=\"" << kHeight - 6 << "\" text-anchor=\"middle\" font-size=\"11\">"
      << html_escape(h.x_label) << "</text>\n";
  svg << "</svg>\n";
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
