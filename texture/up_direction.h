// The vertical of a reconstruction in its (SfM) frame, from the cameras and
// the surface.
//
// Photos are held nearly level, so each camera's x axis (image right) is
// nearly horizontal whatever the camera's pitch: up is the direction most
// orthogonal to the x axes, the eigenvector of the smallest eigenvalue of
// sum x x^T (its sign from the mean camera up). That is ill-conditioned when
// the two smallest eigenvalues are close: x axes nearly parallel (all photos
// facing one way, a drone flying one heading) or not near any plane (photos
// rolled at random). Then the dominant ground plane of the surface (the
// RANSAC plane with the most points whose normal is near the cameras' up)
// gives the vertical, and last the mean camera up (-y of the photos), which
// leans with the cameras' mean pitch.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "texture/texture_view.h"

namespace hos::texture {

// What placement needs of a registered photo.
struct CameraPose {
  std::string name;
  Eigen::Matrix3d cam_from_world = Eigen::Matrix3d::Identity();  // rows: camera x, y, z in world coordinates
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();              // world coordinates
};
std::vector<CameraPose> camera_poses(const std::vector<TextureView>& views);
std::vector<CameraPose> camera_poses(const SparseModel& model);

// How the vertical was found.
enum class UpMethod { kGravity, kGroundPlane, kMeanCameraUp, kGps };
const char* up_method_name(UpMethod method);  // "gravity", "ground plane", "mean camera up", "GPS"

struct UpOptions {
  // Camera x axes decide when eig0 / eig1 of their mean x x^T is at most this
  // (the bound atan(sqrt(ratio)) on the tilt a systematic roll can cause:
  // 0.05 -> 12.9 deg; random roll averages out far below it).
  double max_eigenvalue_ratio = 0.05;
  // Ground plane: normal within this angle of the reference up, points
  // within inlier_fraction_of_size * (robust model size) of the plane, at
  // least min_inlier_fraction of the points.
  double ground_max_angle_deg = 30.0;
  double inlier_fraction_of_size = 0.005;
  double min_inlier_fraction = 0.1;
  int ransac_iterations = 500;
  int max_points = 20000;  // points subsampled evenly for the ground plane
};

struct UpEstimate {
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();  // unit, world (SfM) frame
  UpMethod method = UpMethod::kMeanCameraUp;
  // Ascending eigenvalues of the mean of x x^T over the camera x axes.
  Eigen::Vector3d x_axis_eigenvalues = Eigen::Vector3d::Zero();
  std::string fallback_reason;  // why the camera x axes did not decide; empty when they did
};

// The mean of the cameras' up directions (-y of the image), unit; +Y of the
// world for no cameras or when they cancel.
Eigen::Vector3d mean_camera_up(const std::vector<CameraPose>& cameras);

// The normal of the plane with the most points among those whose normal is
// within options.ground_max_angle_deg of reference_up, refined by a least-
// squares fit to its inliers and turned towards reference_up; nothing when
// no such plane holds options.min_inlier_fraction of the points.
std::optional<Eigen::Vector3d> ground_plane_normal(const std::vector<Eigen::Vector3f>& points,
                                                   const Eigen::Vector3d& reference_up,
                                                   const UpOptions& options = {});

// Camera x axes, then the ground plane of points (may be empty), then the
// mean camera up, as the file comment says.
UpEstimate estimate_up(const std::vector<CameraPose>& cameras,
                       const std::vector<Eigen::Vector3f>& points,
                       const UpOptions& options = {});

}  // namespace hos::texture
