// Geographic positions (WGS84) and the local east-north-up frame around a
// reference position, for placing a model from the photos' GPS and writing
// GPS positions of synthetic views.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

namespace hos {

// A WGS84 position as EXIF GPS gives it.
struct GeoPosition {
  double latitude_deg = 0.0;         // north positive, -90..90
  double longitude_deg = 0.0;        // east positive
  std::optional<double> altitude_m;  // ellipsoidal/sea-level height; unknown for many phones
};

// A photo's position, by the photo's name in the workspace; none when its
// EXIF has no GPS.
struct PhotoGps {
  std::string name;
  std::optional<GeoPosition> gps;
};

// Earth-centred Earth-fixed coordinates (metres) of a position; a missing
// altitude counts as 0.
Eigen::Vector3d ecef_from_geodetic(const GeoPosition& position);
// The inverse (iterative, sub-millimetre away from the poles; always with altitude).
GeoPosition geodetic_from_ecef(const Eigen::Vector3d& x);

// The local tangent frame at a reference position: x east, y north, z up
// (metres), origin at the reference (its altitude, 0 if unknown).
class EnuFrame {
 public:
  explicit EnuFrame(const GeoPosition& reference);
  Eigen::Vector3d enu_from_geodetic(const GeoPosition& position) const;
  GeoPosition geodetic_from_enu(const Eigen::Vector3d& enu) const;
  const GeoPosition& reference() const { return reference_; }

 private:
  GeoPosition reference_;
  Eigen::Vector3d origin_ecef_;
  Eigen::Matrix3d enu_from_ecef_;  // rows: east, north, up
};

}  // namespace hos
