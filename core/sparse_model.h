// A COLMAP sparse reconstruction: cameras, posed images and 3D points.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/camera.h"

namespace hos {

// A keypoint of an image; point3d_id is -1 when it has no 3D point.
struct Keypoint {
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();
  std::int64_t point3d_id = -1;
};

// A registered image. The pose maps world to camera coordinates:
// x_in_cam = cam_from_world_rotation * x_in_world + cam_from_world_translation.
struct ImageRecord {
  int id = 0;
  int camera_id = 0;
  std::string name;  // path relative to the image folder, as COLMAP stores it
  Eigen::Quaterniond cam_from_world_rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d cam_from_world_translation = Eigen::Vector3d::Zero();
  std::vector<Keypoint> keypoints;

  Eigen::Matrix3d rotation() const { return cam_from_world_rotation.toRotationMatrix(); }
  // Camera centre in world coordinates: -R^T t.
  Eigen::Vector3d center() const;
  // Unit viewing direction (camera +z) in world coordinates.
  Eigen::Vector3d viewing_direction() const;
  Eigen::Vector3d cam_from_world(const Eigen::Vector3d& x_in_world) const;
  Eigen::Vector3d world_from_cam(const Eigen::Vector3d& x_in_cam) const;
};

// One element of a 3D point's track.
struct TrackElement {
  int image_id = 0;
  int keypoint_index = 0;
};

struct Point3D {
  std::int64_t id = 0;
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  std::array<std::uint8_t, 3> color{0, 0, 0};
  double error = 0.0;  // mean reprojection error in pixels
  std::vector<TrackElement> track;
};

struct SparseModel {
  std::map<int, Camera> cameras;
  std::map<int, ImageRecord> images;
  std::map<std::int64_t, Point3D> points;

  const Camera& camera_of(const ImageRecord& image) const;
  // Image by name, or nullptr.
  const ImageRecord* find_image(const std::string& name) const;
};

// Summary figures COLMAP users look at after mapping.
struct SparseModelStats {
  int num_cameras = 0;
  int num_images = 0;
  std::int64_t num_points = 0;
  double mean_reprojection_error_px = 0.0;
  double mean_track_length = 0.0;
  double mean_observations_per_image = 0.0;
};
SparseModelStats compute_stats(const SparseModel& model);

}  // namespace hos
