// Camera rotations for test scenes.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hos::testing {

// The rotation of a camera looking along `forward` with the world's `up`
// upwards in its image (image y along -up): rows x = forward x up, y, z =
// forward, normalised.
inline Eigen::Matrix3d cam_from_world_looking(const Eigen::Vector3d& forward, const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = forward.normalized();
  const Eigen::Vector3d x = z.cross(up).normalized();
  Eigen::Matrix3d cam_from_world;
  cam_from_world.row(0) = x.transpose();
  cam_from_world.row(1) = z.cross(x).transpose();
  cam_from_world.row(2) = z.transpose();
  return cam_from_world;
}

}  // namespace hos::testing
