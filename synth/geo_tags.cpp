#include "synth/geo_tags.h"

#include <cmath>
#include <exiv2/exiv2.hpp>
#include <sstream>

#include "core/error.h"

namespace hos::synth {
namespace {

// Degrees as EXIF's three rationals: whole degrees, whole minutes, seconds
// in millionths (about 30 micrometres on the ground).
std::string degrees_minutes_seconds(double degrees) {
  const double a = std::abs(degrees);
  long d = static_cast<long>(a);
  long m = static_cast<long>((a - double(d)) * 60.0);
  long micro_s = std::lround(((a - double(d)) * 60.0 - double(m)) * 60.0 * 1e6);
  if (micro_s >= 60000000L) micro_s -= 60000000L, ++m;
  if (m >= 60) m -= 60, ++d;
  std::ostringstream out;
  out << d << "/1 " << m << "/1 " << micro_s << "/1000000";
  return out.str();
}

}  // namespace

Eigen::Vector3d enu_from_scene(const Eigen::Vector3d& x, double metres_per_unit) {
  return metres_per_unit * Eigen::Vector3d(x.x(), x.z(), -x.y());
}

GeoPosition scene_gps_position(const Eigen::Vector3d& x, const GeoPosition& origin, double metres_per_unit) {
  return EnuFrame(origin).geodetic_from_enu(enu_from_scene(x, metres_per_unit));
}

void write_gps_exif(const std::filesystem::path& jpeg, const GeoPosition& p) {
  try {
    auto image = Exiv2::ImageFactory::open(jpeg.string());
    image->readMetadata();
    Exiv2::ExifData& exif = image->exifData();
    exif["Exif.GPSInfo.GPSVersionID"] = "2 3 0 0";
    exif["Exif.GPSInfo.GPSLatitudeRef"] = p.latitude_deg >= 0 ? "N" : "S";
    exif["Exif.GPSInfo.GPSLatitude"] = degrees_minutes_seconds(p.latitude_deg);
    exif["Exif.GPSInfo.GPSLongitudeRef"] = p.longitude_deg >= 0 ? "E" : "W";
    exif["Exif.GPSInfo.GPSLongitude"] = degrees_minutes_seconds(p.longitude_deg);
    if (p.altitude_m) {
      exif["Exif.GPSInfo.GPSAltitudeRef"] = *p.altitude_m >= 0 ? "0" : "1";
      std::ostringstream altitude;
      altitude << std::lround(std::abs(*p.altitude_m) * 1000.0) << "/1000";
      exif["Exif.GPSInfo.GPSAltitude"] = altitude.str();
    }
    image->writeMetadata();
  } catch (const Exiv2::AnyError& e) {
    throw OutputError(jpeg.string(), std::string("the GPS EXIF: ") + e.what());
  }
}

}  // namespace hos::synth
