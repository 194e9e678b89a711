#include "texture/up_direction.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "core/statistics.h"

namespace hos::texture {
namespace {

Eigen::Vector3d camera_up(const CameraPose& c) { return -c.cam_from_world.row(1).transpose(); }
Eigen::Vector3d camera_right(const CameraPose& c) { return c.cam_from_world.row(0).transpose(); }
Eigen::Vector3d camera_forward(const CameraPose& c) { return c.cam_from_world.row(2).transpose(); }

// Mean of x x^T over the camera x axes, eigen-decomposed (ascending).
Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> x_axis_moments(const std::vector<CameraPose>& cameras) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (const CameraPose& c : cameras) m += camera_right(c) * camera_right(c).transpose();
  if (!cameras.empty()) m /= static_cast<double>(cameras.size());
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(m);
}

// Turns a vertical towards the cameras' up; for cameras looking straight
// down (their up is horizontal) towards the side they look away from.
Eigen::Vector3d orient_up(const Eigen::Vector3d& up, const std::vector<CameraPose>& cameras) {
  Eigen::Vector3d mean_up = Eigen::Vector3d::Zero(), mean_forward = Eigen::Vector3d::Zero();
  for (const CameraPose& c : cameras) {
    mean_up += camera_up(c);
    mean_forward += camera_forward(c);
  }
  const double n = std::max<double>(1.0, static_cast<double>(cameras.size()));
  const double along_up = up.dot(mean_up) / n;
  if (std::abs(along_up) >= 0.1) return along_up < 0 ? Eigen::Vector3d(-up) : up;
  return up.dot(mean_forward) > 0 ? Eigen::Vector3d(-up) : up;
}

// Diagonal of the box of the 1st to 99th percentiles per axis: a size that
// stray points do not inflate.
double robust_size(const std::vector<Eigen::Vector3f>& points) {
  double squared = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<float> values(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) values[i] = points[i][axis];
    const double extent = quantile(values, 0.99) - quantile(values, 0.01);
    squared += extent * extent;
  }
  return std::sqrt(squared);
}

std::vector<Eigen::Vector3f> subsample(const std::vector<Eigen::Vector3f>& points, int max_points) {
  if (static_cast<int>(points.size()) <= max_points) return points;
  std::vector<Eigen::Vector3f> out;
  out.reserve(static_cast<std::size_t>(max_points));
  const double step = double(points.size()) / max_points;
  for (int i = 0; i < max_points; ++i) out.push_back(points[static_cast<std::size_t>(i * step)]);
  return out;
}

}  // namespace

std::vector<CameraPose> camera_poses(const std::vector<TextureView>& views) {
  std::vector<CameraPose> out;
  out.reserve(views.size());
  for (const TextureView& v : views) out.push_back({v.name, v.pose.rotation(), v.pose.center()});
  return out;
}

std::vector<CameraPose> camera_poses(const SparseModel& model) {
  std::vector<CameraPose> out;
  for (const auto& [id, image] : model.images) out.push_back({image.name, image.rotation(), image.center()});
  return out;
}

const char* up_method_name(UpMethod method) {
  switch (method) {
    case UpMethod::kGravity:
      return "gravity";
    case UpMethod::kGroundPlane:
      return "ground plane";
    case UpMethod::kMeanCameraUp:
      return "mean camera up";
    case UpMethod::kGps:
      return "GPS";
  }
  return "?";
}

Eigen::Vector3d mean_camera_up(const std::vector<CameraPose>& cameras) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const CameraPose& c : cameras) sum += camera_up(c);
  if (sum.norm() < 1e-9) return Eigen::Vector3d::UnitY();
  return sum.normalized();
}

std::optional<Eigen::Vector3d> ground_plane_normal(const std::vector<Eigen::Vector3f>& all_points,
                                                   const Eigen::Vector3d& reference_up,
                                                   const UpOptions& options) {
  const std::vector<Eigen::Vector3f> points = subsample(all_points, options.max_points);
  if (points.size() < 3) return std::nullopt;
  const double threshold = options.inlier_fraction_of_size * robust_size(points);
  if (!(threshold > 0.0)) return std::nullopt;
  const double min_cos = std::cos(options.ground_max_angle_deg * std::numbers::pi / 180.0);
  std::mt19937 rng(1);
  std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
  std::size_t best_count = 0;
  Eigen::Vector3d best_normal = reference_up;
  double best_offset = 0.0;
  for (int iteration = 0; iteration < options.ransac_iterations; ++iteration) {
    const Eigen::Vector3d a = points[pick(rng)].cast<double>(), b = points[pick(rng)].cast<double>(),
                          c = points[pick(rng)].cast<double>();
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    if (cross.norm() < 1e-12) continue;
    const Eigen::Vector3d normal = cross.normalized();
    if (std::abs(normal.dot(reference_up)) < min_cos) continue;
    const double offset = normal.dot(a);
    std::size_t count = 0;
    for (const auto& p : points) count += std::abs(normal.dot(p.cast<double>()) - offset) <= threshold ? 1 : 0;
    if (count > best_count) best_count = count, best_normal = normal, best_offset = offset;
  }
  if (double(best_count) < options.min_inlier_fraction * double(points.size())) return std::nullopt;
  // Least squares on the inliers: the direction of least spread.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> inliers;
  for (const auto& p : points) {
    if (std::abs(best_normal.dot(p.cast<double>()) - best_offset) <= threshold) inliers.push_back(p.cast<double>());
  }
  for (const auto& p : inliers) mean += p;
  mean /= double(inliers.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& p : inliers) scatter += (p - mean) * (p - mean).transpose();
  Eigen::Vector3d normal = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvectors().col(0);
  if (normal.dot(reference_up) < 0) normal = -normal;
  if (normal.dot(reference_up) < min_cos) return std::nullopt;
  return normal;
}

UpEstimate estimate_up(const std::vector<CameraPose>& cameras,
                       const std::vector<Eigen::Vector3f>& points,
                       const UpOptions& options) {
  UpEstimate estimate;
  const auto moments = x_axis_moments(cameras);
  const Eigen::Vector3d& eig = moments.eigenvalues();
  estimate.x_axis_eigenvalues = eig;
  if (cameras.size() >= 2 && eig[1] > 1e-12 && eig[0] <= options.max_eigenvalue_ratio * eig[1]) {
    estimate.up = orient_up(moments.eigenvectors().col(0), cameras);
    estimate.method = UpMethod::kGravity;
    return estimate;
  }
  // When the x axes share one direction it is still horizontal: the
  // reference up is the mean up made orthogonal to it.
  Eigen::Vector3d reference = mean_camera_up(cameras);
  const bool one_direction = eig[2] > 0 && eig[1] < 0.1 * eig[2];
  if (one_direction) {
    const Eigen::Vector3d x = moments.eigenvectors().col(2);
    const Eigen::Vector3d level = reference - reference.dot(x) * x;
    if (level.norm() > 1e-6) reference = level.normalized();
  }
  estimate.fallback_reason = cameras.size() < 2 ? "fewer than 2 cameras"
                             : one_direction    ? "the camera x axes are nearly parallel"
                                                : "the camera x axes do not lie near one plane (photos not level)";
  if (const auto ground = ground_plane_normal(points, reference, options)) {
    estimate.up = *ground;
    estimate.method = UpMethod::kGroundPlane;
    return estimate;
  }
  estimate.up = reference;
  estimate.method = UpMethod::kMeanCameraUp;
  return estimate;
}

}  // namespace hos::texture
