#include "texture/placement.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/statistics.h"

namespace hos::texture {
namespace {

// ENU (east, north, up) -> glTF's axes (+X east, +Y up, +Z south).
Eigen::Matrix3d gltf_from_enu() {
  Eigen::Matrix3d m;
  m << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  return m;
}

Eigen::Vector3d horizontal(const Eigen::Vector3d& v, const Eigen::Vector3d& up) { return v - v.dot(up) * up; }

// Rotation of the SfM frame taking up to +Y and the cameras' mean viewing
// direction (horizontally) to -Z; cameras looking straight down count with
// the top of their image.
Eigen::Matrix3d upright_rotation(const Eigen::Vector3d& up, const std::vector<CameraPose>& cameras) {
  Eigen::Vector3d forward = Eigen::Vector3d::Zero();
  for (const CameraPose& c : cameras) forward += horizontal(c.cam_from_world.row(2).transpose(), up);
  if (forward.norm() < 0.1 * double(cameras.size()) && !cameras.empty()) {
    const CameraPose& first = cameras.front();
    forward = horizontal(first.cam_from_world.row(2).transpose() - first.cam_from_world.row(1).transpose(), up);
  }
  if (forward.norm() < 1e-9) forward = up.unitOrthogonal();
  const Eigen::Vector3d z = -forward.normalized();
  Eigen::Matrix3d r;
  r.row(1) = up.transpose();
  r.row(2) = z.transpose();
  r.row(0) = up.cross(z).transpose();
  return r;
}

const CameraPose& find_camera(const std::vector<CameraPose>& cameras, const std::string& name) {
  for (const CameraPose& c : cameras) {
    if (c.name == name) return c;
  }
  throw ConfigError("texture.scale_distance", "photo " + name + " is not among the registered photos");
}

double measured_scale(const std::vector<CameraPose>& cameras, const ScaleDistance& d) {
  if (d.photo_a == d.photo_b) throw ConfigError("texture.scale_distance", "needs two different photos");
  if (!(d.metres > 0.0) || !std::isfinite(d.metres)) {
    throw ConfigError("texture.scale_distance", "the distance must be a positive number of metres");
  }
  const double model = (find_camera(cameras, d.photo_a).centre - find_camera(cameras, d.photo_b).centre).norm();
  if (!(model > 1e-12)) {
    throw ConfigError("texture.scale_distance",
                      "the camera centres of " + d.photo_a + " and " + d.photo_b + " coincide");
  }
  return d.metres / model;
}

// Centre of the footprint (x, z) and the base height (y) of points
// transformed by the linear part.
Eigen::Vector3d footprint_origin(const std::vector<Eigen::Vector3f>& vertices,
                                 const Eigen::Matrix3d& linear,
                                 const Eigen::Vector3d& offset,
                                 const PlacementOptions& options) {
  if (vertices.empty()) return offset;
  std::vector<float> axis[3];
  for (auto& a : axis) a.reserve(vertices.size());
  for (const Eigen::Vector3f& v : vertices) {
    const Eigen::Vector3d p = linear * v.cast<double>() + offset;
    for (int k = 0; k < 3; ++k) axis[k].push_back(static_cast<float>(p[k]));
  }
  const double lo = options.footprint_percentile, hi = 1.0 - options.footprint_percentile;
  const double x = 0.5 * (double(quantile(axis[0], lo)) + quantile(axis[0], hi));
  const double z = 0.5 * (double(quantile(axis[2], lo)) + quantile(axis[2], hi));
  return {x, quantile(axis[1], options.base_percentile), z};
}

std::string format_metres(double m) {
  std::ostringstream out;
  out.precision(m < 10 ? 2 : 3);
  out << m << " m";
  return out.str();
}

}  // namespace

ScaleDistance parse_scale_distance(const std::string& text) {
  std::istringstream words(text);
  ScaleDistance d;
  std::string metres, extra;
  if (!(words >> d.photo_a >> d.photo_b >> metres) || (words >> extra)) {
    throw ConfigError("texture.scale_distance", "'" + text + "': expected 'A.jpg B.jpg METRES'");
  }
  std::size_t used = 0;
  try {
    d.metres = std::stod(metres, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != metres.size() || !(d.metres > 0.0) || !std::isfinite(d.metres)) {
    throw ConfigError("texture.scale_distance", "'" + metres + "' is not a positive number of metres");
  }
  return d;
}

std::string Placement::units_text() const {
  if (gps && metric && units == "metres from GPS") {
    return format_message("units: ", units, " (", gps->inliers, " photos, residual ",
                          format_metres(gps->rms_residual_m), ")");
  }
  if (metric) return "units: " + units;
  return "units: " + units + ", because: " + units_reason;
}

Placement place_model(const std::vector<Eigen::Vector3f>& vertices,
                      const std::vector<CameraPose>& cameras,
                      const PlacementInput& input,
                      const PlacementOptions& options) {
  Placement p;
  p.up = estimate_up(cameras, vertices, options.up);
  Eigen::Matrix3d rotation = upright_rotation(p.up.up, cameras);
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  p.units = "arbitrary (COLMAP's)";
  if (input.scale_distance) {
    p.scale = measured_scale(cameras, *input.scale_distance);
    p.metric = true;
    p.units = "metres from the measured distance between " + input.scale_distance->photo_a + " and " +
              input.scale_distance->photo_b;
  } else if (input.photo_positions.empty()) {
    p.units_reason = "no GPS";
  } else {
    p.gps = align_to_gps(cameras, input.photo_positions, p.up.up, options.gps);
    if (!p.gps->usable) {
      p.units_reason = p.gps->reason;
    } else {
      const Similarity& s = p.gps->enu_from_model;
      p.scale = s.scale;
      p.metric = true;
      p.units = "metres from GPS";
      rotation = gltf_from_enu() * s.rotation;
      offset = gltf_from_enu() * s.translation;
      if (p.gps->vertical_from_gps) {
        p.up.up = s.rotation.transpose() * Eigen::Vector3d::UnitZ();
        p.up.method = UpMethod::kGps;
      }
    }
  }
  const Eigen::Matrix3d linear = p.scale * rotation;
  const Eigen::Vector3d origin = footprint_origin(vertices, linear, offset, options);
  p.root_matrix.topLeftCorner<3, 3>() = linear;
  p.root_matrix.topRightCorner<3, 1>() = offset - origin;
  if (p.metric && p.gps && p.gps->usable) {
    GeoPosition geo = p.gps->frame.geodetic_from_enu(gltf_from_enu().transpose() * origin);
    if (!p.gps->has_altitude) geo.altitude_m.reset();
    p.geo_origin = geo;
  }
  return p;
}

void apply_root_matrix(TexturedMesh& mesh) {
  const Eigen::Matrix3d linear = mesh.root_matrix.topLeftCorner<3, 3>();
  const Eigen::Vector3d translation = mesh.root_matrix.topRightCorner<3, 1>();
  const Eigen::Matrix3d normal_matrix = linear.inverse().transpose();
  for (auto& v : mesh.positions) v = (linear * v.cast<double>() + translation).cast<float>();
  for (auto& n : mesh.normals) {
    const Eigen::Vector3d m = normal_matrix * n.cast<double>();
    if (m.norm() > 0) n = m.normalized().cast<float>();
  }
  mesh.root_matrix.setIdentity();
}

}  // namespace hos::texture
