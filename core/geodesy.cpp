#include "core/geodesy.h"

#include <cmath>
#include <numbers>

namespace hos {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;
// WGS84 ellipsoid.
constexpr double kSemiMajorAxis = 6378137.0;
constexpr double kFlattening = 1.0 / 298.257223563;
constexpr double kEccentricitySquared = kFlattening * (2.0 - kFlattening);

double prime_vertical_radius(double latitude_rad) {
  const double s = std::sin(latitude_rad);
  return kSemiMajorAxis / std::sqrt(1.0 - kEccentricitySquared * s * s);
}

}  // namespace

Eigen::Vector3d ecef_from_geodetic(const GeoPosition& p) {
  const double lat = p.latitude_deg * kDegree, lon = p.longitude_deg * kDegree;
  const double h = p.altitude_m.value_or(0.0);
  const double n = prime_vertical_radius(lat);
  return {(n + h) * std::cos(lat) * std::cos(lon), (n + h) * std::cos(lat) * std::sin(lon),
          (n * (1.0 - kEccentricitySquared) + h) * std::sin(lat)};
}

GeoPosition geodetic_from_ecef(const Eigen::Vector3d& x) {
  const double p = std::hypot(x.x(), x.y());
  double lat = std::atan2(x.z(), p * (1.0 - kEccentricitySquared));
  double h = 0.0;
  // Fixed-point iteration on latitude and height; converges to well below a
  // millimetre in a few steps away from the poles.
  for (int i = 0; i < 8; ++i) {
    const double n = prime_vertical_radius(lat);
    h = p / std::cos(lat) - n;
    lat = std::atan2(x.z(), p * (1.0 - kEccentricitySquared * n / (n + h)));
  }
  GeoPosition out;
  out.latitude_deg = lat / kDegree;
  out.longitude_deg = std::atan2(x.y(), x.x()) / kDegree;
  out.altitude_m = h;
  return out;
}

EnuFrame::EnuFrame(const GeoPosition& reference) : reference_(reference) {
  origin_ecef_ = ecef_from_geodetic(reference);
  const double lat = reference.latitude_deg * kDegree, lon = reference.longitude_deg * kDegree;
  enu_from_ecef_.row(0) << -std::sin(lon), std::cos(lon), 0.0;
  enu_from_ecef_.row(1) << -std::sin(lat) * std::cos(lon), -std::sin(lat) * std::sin(lon), std::cos(lat);
  enu_from_ecef_.row(2) << std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat);
}

Eigen::Vector3d EnuFrame::enu_from_geodetic(const GeoPosition& position) const {
  GeoPosition p = position;
  if (!p.altitude_m) p.altitude_m = reference_.altitude_m.value_or(0.0);
  return enu_from_ecef_ * (ecef_from_geodetic(p) - origin_ecef_);
}

GeoPosition EnuFrame::geodetic_from_enu(const Eigen::Vector3d& enu) const {
  return geodetic_from_ecef(origin_ecef_ + enu_from_ecef_.transpose() * enu);
}

}  // namespace hos
