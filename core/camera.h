// Camera models as COLMAP defines them (src/base/camera_models.h), with the
// same parameter order, so models read from COLMAP need no conversion.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace hos {

// COLMAP model ids are the enum values.
enum class CameraModel : int {
  kSimplePinhole = 0,  // f, cx, cy
  kPinhole = 1,        // fx, fy, cx, cy
  kSimpleRadial = 2,   // f, cx, cy, k
  kRadial = 3,         // f, cx, cy, k1, k2
  kOpenCV = 4,         // fx, fy, cx, cy, k1, k2, p1, p2
};

// "SIMPLE_PINHOLE", "PINHOLE", ... as COLMAP spells them.
std::string camera_model_name(CameraModel model);
// Throws InputError-free std::invalid_argument for unknown names; callers that
// read files wrap it with the file name.
CameraModel camera_model_from_name(const std::string& name);
// Throws std::invalid_argument for ids hos does not support.
CameraModel camera_model_from_id(int id);
int camera_model_num_params(CameraModel model);

// Intrinsics of one camera. Pixel convention is COLMAP's: the centre of the
// top-left pixel is (0.5, 0.5).
struct Camera {
  int id = 0;
  CameraModel model = CameraModel::kPinhole;
  int width = 0;
  int height = 0;
  std::vector<double> params;

  // Focal lengths and principal point, whatever the model.
  double focal_x() const;
  double focal_y() const;
  double principal_x() const;
  double principal_y() const;
  bool has_distortion() const;

  // Camera coordinates (z forward) to pixel; std::nullopt if z <= 0.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& x_in_cam) const;
  // Pixel to a point on the normalized image plane (x, y, 1), undoing
  // distortion iteratively.
  Eigen::Vector3d unproject(const Eigen::Vector2d& pixel) const;

  // Calibration matrix of the undistorted pinhole part.
  Eigen::Matrix3d calibration_matrix() const;

  // A PINHOLE camera; convenience for tests and the renderer.
  static Camera pinhole(int id, int width, int height, double fx, double fy, double cx, double cy);
};

// Applies the model's distortion to normalized coordinates (x/z, y/z).
Eigen::Vector2d distort_normalized(const Camera& camera, const Eigen::Vector2d& undistorted);
// Inverse of distort_normalized (Newton iterations).
Eigen::Vector2d undistort_normalized(const Camera& camera, const Eigen::Vector2d& distorted);

}  // namespace hos
