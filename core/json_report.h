// The stages' small report files (WS/<stage>/report.json): a histogram as
// JSON and an atomic write. Header-only, so that core itself does not need
// nlohmann/json; the libraries that write reports link it.
#pragma once

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/histogram.h"

namespace hos {

// {"lo": .., "hi": .., "counts": [..]}
inline nlohmann::ordered_json histogram_json(const Histogram& h) {
  nlohmann::ordered_json j;
  j["lo"] = h.lo;
  j["hi"] = h.hi;
  j["counts"] = h.counts;
  return j;
}

// The inverse of histogram_json; throws nlohmann::json::exception if j is
// not one.
inline Histogram histogram_from_json(const nlohmann::json& j) {
  Histogram h;
  h.lo = j.at("lo").get<double>();
  h.hi = j.at("hi").get<double>();
  h.counts = j.at("counts").get<std::vector<std::int64_t>>();
  return h;
}

// j as indented JSON text. File names are bytes, not always UTF-8 (Latin-1
// from an unzipped Windows archive): such bytes become U+FFFD instead of
// nlohmann's exception.
template <typename Json>
std::string json_text(const Json& j, int indent = 2) {
  return j.dump(indent, ' ', false, Json::error_handler_t::replace);
}

// Writes j (indented) atomically; throws OutputError.
inline void write_json_report(const std::filesystem::path& path, const nlohmann::ordered_json& j) {
  const std::string text = json_text(j);
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp);
    out << text << "\n";
    if (!out) throw OutputError(path.string(), "cannot write the report");
  });
}

}  // namespace hos
