#include "mvs/mvs_report.h"

#include "core/json_report.h"

namespace hos::mvs {
namespace {

MvsViewReport view_report(const MvsViewStats& v) {
  MvsViewReport r;
  r.name = v.name;
  r.sources = v.num_sources;
  r.skipped = v.skipped;
  r.pixels = static_cast<std::int64_t>(v.pixels);
  r.valid_pixels = static_cast<std::int64_t>(v.valid_pixels);
  r.coverage = v.pixels > 0 ? double(v.valid_pixels) / double(v.pixels) : 0.0;
  r.seconds = v.seconds;
  return r;
}

nlohmann::ordered_json view_json(const MvsViewReport& v) {
  return {{"name", v.name},      {"sources", v.sources},           {"skipped", v.skipped},
          {"pixels", v.pixels},  {"valid_pixels", v.valid_pixels}, {"coverage", v.coverage},
          {"seconds", v.seconds}};
}

MvsViewReport view_from_json(const nlohmann::ordered_json& j) {
  MvsViewReport v;
  read_key(j, "name", v.name);
  read_key(j, "sources", v.sources);
  read_key(j, "skipped", v.skipped);
  read_key(j, "pixels", v.pixels);
  read_key(j, "valid_pixels", v.valid_pixels);
  read_key(j, "coverage", v.coverage);
  read_key(j, "seconds", v.seconds);
  return v;
}

MvsReport report_from_json(const nlohmann::ordered_json& j) {
  MvsReport r;
  read_key(j, "views", r.views);
  read_key(j, "views_skipped", r.views_skipped);
  read_key(j, "points", r.points);
  read_key(j, "seconds_depth", r.seconds_depth);
  read_key(j, "seconds_fusion", r.seconds_fusion);
  if (const auto views = j.find("per_view"); views != j.end()) {
    for (const auto& v : views->get<std::vector<nlohmann::ordered_json>>()) r.per_view.push_back(view_from_json(v));
  }
  read_key(j, "confidence", r.confidence);
  return r;
}

}  // namespace

MvsReport mvs_report(const MvsResult& result) {
  const MvsStats& s = result.stats;
  MvsReport r;
  r.views = s.views;
  r.views_skipped = s.views_skipped;
  r.points = static_cast<std::int64_t>(s.points);
  r.seconds_depth = s.seconds_depth;
  r.seconds_fusion = s.seconds_fusion;
  for (const MvsViewStats& v : s.per_view) r.per_view.push_back(view_report(v));
  const std::vector<double> confidence(result.points.confidence.begin(), result.points.confidence.end());
  r.confidence = make_count_histogram(confidence, kMaxPlottedConfidence);
  return r;
}

nlohmann::ordered_json to_json(const MvsReport& r) {
  nlohmann::ordered_json views = nlohmann::ordered_json::array();
  for (const MvsViewReport& v : r.per_view) views.push_back(view_json(v));
  return {{"views", r.views},
          {"views_skipped", r.views_skipped},
          {"points", r.points},
          {"seconds_depth", r.seconds_depth},
          {"seconds_fusion", r.seconds_fusion},
          {"per_view", views},
          {"confidence", histogram_json(r.confidence)}};
}

MvsReport read_mvs_report(const std::filesystem::path& path) { return read_json_report(path, report_from_json); }

void write_mvs_report(const std::filesystem::path& path, const MvsResult& result) {
  write_json_report(path, to_json(mvs_report(result)));
}

}  // namespace hos::mvs
