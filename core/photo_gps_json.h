// The photos' GPS positions as JSON: the sfm stage's report.json holds them
// under "photos", and the texture stage reads them from there (hos-texture
// --geo) to place the model. Header-only, as core/json_report.h: core itself
// does not need nlohmann/json.
#pragma once

#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "core/geodesy.h"

namespace hos {

// [{"name": ..., "gps": {"altitude_m" (when known), "latitude_deg",
// "longitude_deg"} or null}, ...] in the photos' order.
inline nlohmann::ordered_json photo_gps_json(const std::vector<PhotoGps>& photos) {
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (const PhotoGps& photo : photos) {
    nlohmann::ordered_json gps = nullptr;
    if (photo.gps) {
      if (photo.gps->altitude_m) gps["altitude_m"] = *photo.gps->altitude_m;
      gps["latitude_deg"] = photo.gps->latitude_deg;
      gps["longitude_deg"] = photo.gps->longitude_deg;
    }
    j.push_back({{"name", photo.name}, {"gps", gps}});
  }
  return j;
}

// The inverse of photo_gps_json; a photo without "gps" has none. Throws
// nlohmann::json::exception when j is not such a list (no array, a photo
// without its name, a position without latitude or longitude, a value of
// another type).
template <typename Json>
std::vector<PhotoGps> photo_gps_from_json(const Json& j) {
  std::vector<PhotoGps> photos;
  for (const Json& photo : j.template get<std::vector<Json>>()) {
    PhotoGps p;
    photo.at("name").get_to(p.name);
    if (const auto gps = photo.find("gps"); gps != photo.end() && !gps->is_null()) {
      p.gps = GeoPosition{};
      gps->at("latitude_deg").get_to(p.gps->latitude_deg);
      gps->at("longitude_deg").get_to(p.gps->longitude_deg);
      if (const auto altitude = gps->find("altitude_m"); altitude != gps->end()) {
        p.gps->altitude_m = altitude->template get<double>();
      }
    }
    photos.push_back(std::move(p));
  }
  return photos;
}

}  // namespace hos
