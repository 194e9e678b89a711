// Real size, orientation and place of a reconstruction from the photos' GPS
// positions: a similarity from the SfM frame to the local east-north-up
// frame (metres) fitted to the camera centres, robustly (RANSAC over
// minimal sets, then least squares on the inliers, Umeyama 1991).
//
// Photos' GPS is noisy (metres, more in altitude), so the fit is used only
// when the positions spread far more than that. Without altitude for every
// photo, or when the altitudes cannot fix the tilt to within
// max_tilt_uncertainty_deg, the vertical is taken from the given up
// direction (gravity) and only the horizontal scale, rotation and offset
// are fitted (the height offset from the altitudes when there are any).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/geodesy.h"
#include "texture/up_direction.h"

namespace hos::texture {

struct PhotoPosition {
  std::string name;  // as the photo is named in the workspace
  GeoPosition gps;
};

// Reads the photos' GPS positions from JSON: an object whose "photos" key
// lists them as the sfm stage's report.json does (core/photo_gps_json.h;
// photos without a position are skipped); an object without "photos" holds
// none. Throws InputError naming the file and the reason (a latitude or
// longitude out of range among them).
std::vector<PhotoPosition> read_photo_positions(const std::filesystem::path& file);

// x -> scale * rotation * x + translation.
struct Similarity {
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d operator()(const Eigen::Vector3d& x) const { return scale * (rotation * x) + translation; }
};

struct GeoAlignmentOptions {
  double min_spread_m = 20.0;       // the GPS positions must spread at least this far (horizontally)
  double inlier_threshold_m = 8.0;  // a photo farther than this (3 times this vertically) is an outlier
  // Altitudes decide the vertical only when they fix it this well (one
  // standard error of the fitted tilt).
  double max_tilt_uncertainty_deg = 0.25;
  int ransac_iterations = 500;
};

struct GeoAlignment {
  bool usable = false;
  std::string reason;       // why not usable ("no GPS", "GPS spread 8 m < 20 m", ...)
  int photos_with_gps = 0;  // registered photos with a GPS position
  int inliers = 0;
  double spread_m = 0.0;              // largest horizontal distance between two inliers
  double rms_residual_m = 0.0;        // over the inliers (horizontal only when the vertical came from gravity)
  bool vertical_from_gps = false;     // 3D fit (else the given up decided the vertical)
  bool has_altitude = false;          // the height offset is known (some inlier had an altitude)
  double tilt_uncertainty_deg = 0.0;  // of the 3D fit, when one was tried
  EnuFrame frame{GeoPosition{}};      // its reference is the mean GPS position
  Similarity enu_from_model;          // SfM frame -> ENU of frame (metres)
};

GeoAlignment align_to_gps(const std::vector<CameraPose>& cameras,
                          const std::vector<PhotoPosition>& positions,
                          const Eigen::Vector3d& up_in_model,
                          const GeoAlignmentOptions& options = {});

}  // namespace hos::texture
