#include "core/camera.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hos {
namespace {

struct ModelInfo {
  CameraModel model;
  const char* name;
  int num_params;
};

constexpr ModelInfo kModels[] = {
    {CameraModel::kSimplePinhole, "SIMPLE_PINHOLE", 3},
    {CameraModel::kPinhole, "PINHOLE", 4},
    {CameraModel::kSimpleRadial, "SIMPLE_RADIAL", 4},
    {CameraModel::kRadial, "RADIAL", 5},
    {CameraModel::kOpenCV, "OPENCV", 8},
};

const ModelInfo& info(CameraModel model) {
  for (const auto& m : kModels) {
    if (m.model == model) return m;
  }
  throw std::invalid_argument("unsupported camera model id " + std::to_string(static_cast<int>(model)));
}

// Models whose first parameter is a single focal length f.
bool has_single_focal(CameraModel model) {
  return model == CameraModel::kSimplePinhole || model == CameraModel::kSimpleRadial || model == CameraModel::kRadial;
}

}  // namespace

std::string camera_model_name(CameraModel model) { return info(model).name; }

CameraModel camera_model_from_name(const std::string& name) {
  for (const auto& m : kModels) {
    if (name == m.name) return m.model;
  }
  throw std::invalid_argument("unsupported camera model '" + name +
                              "' (supported: SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL, "
                              "OPENCV)");
}

CameraModel camera_model_from_id(int id) {
  for (const auto& m : kModels) {
    if (static_cast<int>(m.model) == id) return m.model;
  }
  throw std::invalid_argument("unsupported camera model id " + std::to_string(id));
}

int camera_model_num_params(CameraModel model) { return info(model).num_params; }

double Camera::focal_x() const { return params.at(0); }
double Camera::focal_y() const { return has_single_focal(model) ? params.at(0) : params.at(1); }
double Camera::principal_x() const { return has_single_focal(model) ? params.at(1) : params.at(2); }
double Camera::principal_y() const { return has_single_focal(model) ? params.at(2) : params.at(3); }

bool Camera::has_distortion() const {
  switch (model) {
    case CameraModel::kSimplePinhole:
    case CameraModel::kPinhole:
      return false;
    case CameraModel::kSimpleRadial:
      return params.at(3) != 0.0;
    case CameraModel::kRadial:
      return params.at(3) != 0.0 || params.at(4) != 0.0;
    case CameraModel::kOpenCV:
      for (int i = 4; i < 8; ++i) {
        if (params.at(i) != 0.0) return true;
      }
      return false;
  }
  return false;
}

std::optional<Eigen::Vector2d> Camera::project(const Eigen::Vector3d& x_in_cam) const {
  if (!(x_in_cam.z() > 0.0)) return std::nullopt;
  const Eigen::Vector2d normalized = x_in_cam.head<2>() / x_in_cam.z();
  const Eigen::Vector2d d = distort_normalized(*this, normalized);
  return Eigen::Vector2d(focal_x() * d.x() + principal_x(), focal_y() * d.y() + principal_y());
}

Eigen::Vector3d Camera::unproject(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d distorted((pixel.x() - principal_x()) / focal_x(), (pixel.y() - principal_y()) / focal_y());
  const Eigen::Vector2d u = undistort_normalized(*this, distorted);
  return Eigen::Vector3d(u.x(), u.y(), 1.0);
}

Eigen::Matrix3d Camera::calibration_matrix() const {
  Eigen::Matrix3d k = Eigen::Matrix3d::Identity();
  k(0, 0) = focal_x();
  k(1, 1) = focal_y();
  k(0, 2) = principal_x();
  k(1, 2) = principal_y();
  return k;
}

Camera Camera::pinhole(int id, int width, int height, double fx, double fy, double cx, double cy) {
  Camera c;
  c.id = id;
  c.model = CameraModel::kPinhole;
  c.width = width;
  c.height = height;
  c.params = {fx, fy, cx, cy};
  return c;
}

// Same formulas as COLMAP's camera_models.h, written on normalized coordinates.
Eigen::Vector2d distort_normalized(const Camera& camera, const Eigen::Vector2d& u) {
  const auto& p = camera.params;
  const double x2 = u.x() * u.x();
  const double y2 = u.y() * u.y();
  const double r2 = x2 + y2;
  switch (camera.model) {
    case CameraModel::kSimplePinhole:
    case CameraModel::kPinhole:
      return u;
    case CameraModel::kSimpleRadial:
      return u * (1.0 + p.at(3) * r2);
    case CameraModel::kRadial:
      return u * (1.0 + p.at(3) * r2 + p.at(4) * r2 * r2);
    case CameraModel::kOpenCV: {
      const double k1 = p.at(4), k2 = p.at(5), p1 = p.at(6), p2 = p.at(7);
      const double xy = u.x() * u.y();
      const double radial = 1.0 + k1 * r2 + k2 * r2 * r2;
      return Eigen::Vector2d(u.x() * radial + 2.0 * p1 * xy + p2 * (r2 + 2.0 * x2),
                             u.y() * radial + 2.0 * p2 * xy + p1 * (r2 + 2.0 * y2));
    }
  }
  return u;
}

// Newton's method with a numeric Jacobian; converges in a few steps for the
// distortions real lenses have.
Eigen::Vector2d undistort_normalized(const Camera& camera, const Eigen::Vector2d& distorted) {
  if (!camera.has_distortion()) return distorted;
  Eigen::Vector2d u = distorted;
  constexpr int kMaxIterations = 100;
  constexpr double kStep = 1e-7;
  for (int it = 0; it < kMaxIterations; ++it) {
    const Eigen::Vector2d residual = distort_normalized(camera, u) - distorted;
    if (residual.squaredNorm() < 1e-28) break;
    Eigen::Matrix2d jacobian;
    for (int k = 0; k < 2; ++k) {
      Eigen::Vector2d h = Eigen::Vector2d::Zero();
      h[k] = kStep * std::max(1.0, std::abs(u[k]));
      jacobian.col(k) = (distort_normalized(camera, u + h) - distort_normalized(camera, u - h)) / (2.0 * h[k]);
    }
    const Eigen::Vector2d step = jacobian.partialPivLu().solve(residual);
    if (!step.allFinite()) break;
    u -= step;
    if (step.squaredNorm() < 1e-30) break;
  }
  return u;
}

}  // namespace hos
