#include "core/sparse_model.h"

#include <stdexcept>

namespace hos {

Eigen::Vector3d ImageRecord::center() const {
  return -(cam_from_world_rotation.conjugate() * cam_from_world_translation);
}

Eigen::Vector3d ImageRecord::viewing_direction() const {
  return (cam_from_world_rotation.conjugate() * Eigen::Vector3d::UnitZ()).normalized();
}

Eigen::Vector3d ImageRecord::cam_from_world(const Eigen::Vector3d& x_in_world) const {
  return cam_from_world_rotation * x_in_world + cam_from_world_translation;
}

Eigen::Vector3d ImageRecord::world_from_cam(const Eigen::Vector3d& x_in_cam) const {
  return cam_from_world_rotation.conjugate() * (x_in_cam - cam_from_world_translation);
}

const Camera& SparseModel::camera_of(const ImageRecord& image) const {
  const auto it = cameras.find(image.camera_id);
  if (it == cameras.end()) {
    throw std::out_of_range("image '" + image.name + "' refers to missing camera " + std::to_string(image.camera_id));
  }
  return it->second;
}

const ImageRecord* SparseModel::find_image(const std::string& name) const {
  for (const auto& [id, image] : images) {
    if (image.name == name) return &image;
  }
  return nullptr;
}

SparseModelStats compute_stats(const SparseModel& model) {
  SparseModelStats stats;
  stats.num_cameras = static_cast<int>(model.cameras.size());
  stats.num_images = static_cast<int>(model.images.size());
  stats.num_points = static_cast<std::int64_t>(model.points.size());
  double error_sum = 0.0;
  std::int64_t observations = 0;
  for (const auto& [id, point] : model.points) {
    error_sum += point.error;
    observations += static_cast<std::int64_t>(point.track.size());
  }
  if (stats.num_points > 0) {
    stats.mean_reprojection_error_px = error_sum / static_cast<double>(stats.num_points);
    stats.mean_track_length = static_cast<double>(observations) / static_cast<double>(stats.num_points);
  }
  if (stats.num_images > 0) {
    stats.mean_observations_per_image = static_cast<double>(observations) / static_cast<double>(stats.num_images);
  }
  return stats;
}

}  // namespace hos
