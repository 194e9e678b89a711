// A posed photo as the texture stage uses it: PINHOLE camera, pose, pixels.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/reporter.h"
#include "core/sparse_model.h"
#include "core/undistorted_workspace.h"
#include "core/view_range.h"

namespace hos::texture {

struct TextureView {
  std::string name;
  Camera camera;
  ImageRecord pose;  // keypoints dropped
  cv::Mat image;     // CV_8UC3, BGR
  // CV_8U at the image's size, kMaskedOut where the photo's mask excludes
  // the pixel (core/image_mask.h), grown by one pixel so that no bilinear
  // sample reaches a masked pixel; empty: every pixel usable. A face
  // touching a masked pixel is not seen by the view (texture/visibility.h).
  cv::Mat mask;

  // Continuous pixel coordinates (COLMAP: centre of the top-left pixel is
  // (0.5, 0.5)) and camera-frame depth of a world point.
  Eigen::Vector3d project(const Eigen::Vector3d& x_in_world) const;
};

// Loads every registered image of the workspace, with its mask when the
// workspace has one. Throws InputError for an unreadable image or mask, or
// one whose size differs from its camera's.
std::vector<TextureView> load_texture_views(const UndistortedWorkspace& workspace, Reporter& reporter);
// The registered images of range only (numbered from 0 in image id order).
std::vector<TextureView> load_texture_views(const UndistortedWorkspace& workspace,
                                            Reporter& reporter,
                                            const ViewRange& range);

// Bilinear sample of a CV_8UC3 (BGR) or CV_32F image at continuous pixel
// coordinates (COLMAP convention), clamped at the border. Returns RGB.
Eigen::Vector3f sample_rgb(const cv::Mat& bgr, double x, double y);
float sample_float(const cv::Mat& image, double x, double y);

}  // namespace hos::texture
