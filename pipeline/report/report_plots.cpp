#include "pipeline/report/report_plots.h"

#include <nlohmann/json.hpp>

#include "pipeline/report/svg_plot.h"
#include "pipeline/stages.h"

namespace hos::pipeline {

std::string plot_svg(const StagePlot& plot) {
  const PlotLabels labels{plot.title, plot.x_label};
  switch (plot.kind) {
    case StagePlot::Kind::kBars:
      return svg_bar_chart(plot.bars, plot.y_max, labels);
    case StagePlot::Kind::kLogLine:
      return svg_log_line_plot(plot.values, labels);
    case StagePlot::Kind::kHistograms:
      break;
  }
  if (plot.histograms.size() == 1) return svg_histogram(plot.histograms.front().second, labels);
  return svg_histograms(plot.histograms, labels);
}

void write_stage_plots(std::ostream& html, const StagePaths& paths) {
  for (const StageSpec& spec : pipeline_stages()) {
    try {
      for (const StagePlot& plot : spec.plots(paths)) {
        html << "<div id=\"" << plot.id << "\">" << plot_svg(plot) << "</div>\n";
      }
    } catch (const nlohmann::json::exception&) {
      // A report file of another version or a damaged one: its plots are left out, the page is still written.
    }
  }
}

}  // namespace hos::pipeline
