// The calibration of a camera at the size hos-mvs matched its depth map at
// (pixel (x, y)'s centre is at (x + 0.5, y + 0.5)), for the bench programs
// that read .dmap files (mvs/depth_map_file.h).
#pragma once

#include <Eigen/Core>

#include "core/camera.h"
#include "mvs/patch_match.h"

namespace hos::bench {

inline Eigen::Matrix3d depth_map_calibration(const Camera& camera, const mvs::DepthMap& map) {
  Eigen::Matrix3d K = camera.calibration_matrix();
  K.row(0) *= static_cast<double>(map.depth.cols) / camera.width;
  K.row(1) *= static_cast<double>(map.depth.rows) / camera.height;
  return K;
}

}  // namespace hos::bench
