#include "mvs/mvs_report.h"

#include "core/histogram.h"
#include "core/json_report.h"

namespace hos::mvs {
namespace {

nlohmann::ordered_json view_json(const MvsViewStats& v) {
  return {{"name", v.name},
          {"sources", v.num_sources},
          {"skipped", v.skipped},
          {"pixels", v.pixels},
          {"valid_pixels", v.valid_pixels},
          {"coverage", v.pixels > 0 ? double(v.valid_pixels) / double(v.pixels) : 0.0},
          {"seconds", v.seconds}};
}

}  // namespace

nlohmann::ordered_json mvs_report_json(const MvsResult& result) {
  const MvsStats& s = result.stats;
  nlohmann::ordered_json views = nlohmann::ordered_json::array();
  for (const MvsViewStats& v : s.per_view) views.push_back(view_json(v));
  const std::vector<double> confidence(result.points.confidence.begin(), result.points.confidence.end());
  return {{"views", s.views},
          {"views_skipped", s.views_skipped},
          {"points", s.points},
          {"seconds_depth", s.seconds_depth},
          {"seconds_fusion", s.seconds_fusion},
          {"per_view", views},
          {"confidence", histogram_json(make_count_histogram(confidence, kMaxPlottedConfidence))}};
}

void write_mvs_report(const std::filesystem::path& path, const MvsResult& result) {
  write_json_report(path, mvs_report_json(result));
}

}  // namespace hos::mvs
