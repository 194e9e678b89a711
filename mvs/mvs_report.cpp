#include "mvs/mvs_report.h"

#include "core/histogram.h"
#include "core/json_report.h"

namespace hos::mvs {

nlohmann::ordered_json mvs_report_json(const MvsResult& result) {
  const MvsStats& s = result.stats;
  nlohmann::ordered_json j;
  j["views"] = s.views;
  j["views_skipped"] = s.views_skipped;
  j["points"] = s.points;
  j["seconds_depth"] = s.seconds_depth;
  j["seconds_fusion"] = s.seconds_fusion;
  nlohmann::ordered_json views = nlohmann::ordered_json::array();
  for (const MvsViewStats& v : s.per_view) {
    nlohmann::ordered_json view;
    view["name"] = v.name;
    view["sources"] = v.num_sources;
    view["skipped"] = v.skipped;
    view["pixels"] = v.pixels;
    view["valid_pixels"] = v.valid_pixels;
    view["coverage"] = v.pixels > 0 ? double(v.valid_pixels) / double(v.pixels) : 0.0;
    view["seconds"] = v.seconds;
    views.push_back(view);
  }
  j["per_view"] = views;
  const std::vector<double> confidence(result.points.confidence.begin(), result.points.confidence.end());
  j["confidence"] = histogram_json(make_count_histogram(confidence, kMaxPlottedConfidence));
  return j;
}

void write_mvs_report(const std::filesystem::path& path, const MvsResult& result) {
  write_json_report(path, mvs_report_json(result));
}

}  // namespace hos::mvs
