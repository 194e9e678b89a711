// The stages' small report files (WS/<stage>/report.json): a histogram as
// JSON, an atomic write and the checked read of a report. Header-only, so
// that core itself does not need nlohmann/json; the libraries that write
// reports link it.
#pragma once

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

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
template <typename Json>
Histogram histogram_from_json(const Json& j) {
  Histogram h;
  j.at("lo").get_to(h.lo);
  j.at("hi").get_to(h.hi);
  j.at("counts").get_to(h.counts);
  return h;
}

// Named values in their order, as {"name": value, ...}: a stage's steps and
// their seconds.
using NamedValues = std::vector<std::pair<std::string, double>>;
inline nlohmann::ordered_json named_values_json(const NamedValues& values) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [name, value] : values) j[name] = value;
  return j;
}

// j as indented JSON text. File names are bytes, not always UTF-8 (Latin-1
// from an unzipped Windows archive): such bytes become U+FFFD instead of
// nlohmann's exception.
template <typename Json>
std::string json_text(const Json& j, int indent = 2) {
  return j.dump(indent, ' ', false, Json::error_handler_t::replace);
}

// Sets value from j[key] when j has the key (a report of an older version
// may lack it: the value keeps its default); throws
// nlohmann::json::exception when the key holds another type.
template <typename Json, typename T>
void read_key(const Json& j, const char* key, T& value) {
  if (const auto it = j.find(key); it != j.end()) it->get_to(value);
}
template <typename Json>
void read_key(const Json& j, const char* key, Histogram& value) {
  if (const auto it = j.find(key); it != j.end()) value = histogram_from_json(*it);
}
template <typename Json>
void read_key(const Json& j, const char* key, NamedValues& values) {
  if (const auto it = j.find(key); it != j.end()) {
    for (const auto& [name, value] : it->items()) values.emplace_back(name, value.template get<double>());
  }
}

// The report a stage wrote to path, as from_object makes it of the file's
// JSON object (ordered: lists of named steps keep their order). Throws
// InputError naming the file when it is missing, not JSON, not an object,
// or a value has the wrong type.
template <typename FromObject>
auto read_json_report(const std::filesystem::path& path, FromObject from_object)
    -> decltype(from_object(nlohmann::ordered_json())) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), "no report: cannot be read");
  try {
    const nlohmann::ordered_json j = nlohmann::ordered_json::parse(in);
    if (!j.is_object()) throw InputError(path.string(), "not a report: the file holds no JSON object");
    return from_object(j);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path.string(), std::string("malformed report: ") + e.what());
  }
}

// Writes j (indented) atomically; throws OutputError.
inline void write_json_report(const std::filesystem::path& path, const nlohmann::ordered_json& j) {
  const std::string text = json_text(j);
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp);
    out << text << "\n";
    if (!out) throw OutputError(path.string(), "the report");
  });
}

}  // namespace hos
