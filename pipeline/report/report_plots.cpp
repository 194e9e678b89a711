#include "pipeline/report/report_plots.h"

#include "core/error.h"
#include "pipeline/report/svg_plot.h"
#include "pipeline/stages.h"

namespace hos::pipeline {

std::string plot_svg(const StagePlot& plot) {
  const PlotLabels labels{plot.title, plot.x_label, plot.y_label};
  switch (plot.kind) {
    case StagePlot::Kind::kBars:
      return svg_bar_chart(plot.bars, plot.y_max, labels);
    case StagePlot::Kind::kLogLine:
      return svg_log_line_plot(plot.values, labels, plot.segment_lengths);
    case StagePlot::Kind::kHistograms:
      break;
  }
  if (plot.histograms.size() == 1) return svg_histogram(plot.histograms.front().second, labels);
  return svg_histograms(plot.histograms, labels);
}

std::string stage_time_svg(const RunRecord& record) {
  std::vector<std::string> stages;
  std::vector<double> wall, cpu;
  for (const StageSpec& spec : pipeline_stages()) {
    const auto it = record.stages.find(spec.name);
    if (it == record.stages.end() || it->second.state == "running" || it->second.state == "submitted") continue;
    stages.push_back(spec.name);
    wall.push_back(it->second.wall_seconds);
    cpu.push_back(it->second.cpu_seconds);  // 0 where not measured (Slurm)
  }
  if (stages.empty()) return "";
  return svg_horizontal_bars(stages, {{"wall time", wall}, {"CPU time", cpu}},
                             {"where the time went, per stage", "time (s)", ""});
}

void write_stage_plots(std::ostream& html, const StagePaths& paths) {
  for (const StageSpec& spec : pipeline_stages()) {
    try {
      for (const StagePlot& plot : spec.plots(paths)) {
        html << "<div id=\"" << plot.id << "\">" << plot_svg(plot) << "</div>\n";
      }
    } catch (const InputError&) {
      // A report file missing or damaged: its plots are left out, the page is still written.
    }
  }
}

}  // namespace hos::pipeline
