// GPS positions of synthetic views: the scene placed on Earth (its origin at
// a chosen WGS84 position, a scene unit a chosen number of metres; east =
// +x, north = +z, up = -y, the scene's up), and written into a JPEG's EXIF
// GPS tags as a phone would (libexiv2).
#pragma once

#include <Eigen/Core>
#include <filesystem>

#include "core/geodesy.h"

namespace hos::synth {

// East-north-up metres of a scene point, the scene origin at (0, 0, 0).
Eigen::Vector3d enu_from_scene(const Eigen::Vector3d& x_in_scene, double metres_per_unit);

// The WGS84 position of a scene point (with altitude).
GeoPosition scene_gps_position(const Eigen::Vector3d& x_in_scene, const GeoPosition& origin, double metres_per_unit);

// Sets the GPS IFD of a JPEG file (version, latitude, longitude, their
// references, and the altitude when known) in place. Throws OutputError.
void write_gps_exif(const std::filesystem::path& jpeg, const GeoPosition& position);

}  // namespace hos::synth
