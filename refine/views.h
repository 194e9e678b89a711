// The photos the refinement compares: posed pinhole cameras with grey-level
// image pyramids, and per-view depth buffers of the current mesh for
// visibility (render/rasterizer.h).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "core/camera.h"
#include "core/reporter.h"
#include "core/sparse_model.h"
#include "core/types.h"
#include "core/undistorted_workspace.h"

namespace hos::refine {

struct RefineView {
  Camera camera;  // undistorted (PINHOLE or SIMPLE_PINHOLE)
  ImageRecord pose;
  // pose's rotation as a matrix: projecting is the refinement's inner loop.
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  // Grey levels, CV_16U (65535 = white); pyramid[l] is 1/2^l of the photo
  // (box filtered, so pixel centres map as x_l = x_0 / 2^l).
  std::vector<cv::Mat> pyramid;
  // masks[l]: CV_8U at pyramid[l]'s size, kMaskedOut where the photo's mask
  // (core/image_mask.h) excludes a pixel the level's pixel averages, grown
  // by one pixel so that no bilinear sample reaches one; empty: every pixel
  // usable. A masked sample counts as outside the image.
  std::vector<cv::Mat> masks;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // camera centre in world coordinates
  // The current mesh's camera z at the size of pyramid level depth_level,
  // CV_32F, +inf where empty.
  cv::Mat depth;
  int depth_level = 0;

  // World point to the pixel of pyramid level `level` (COLMAP pixel
  // convention), with the camera-frame depth; nothing behind the camera.
  std::optional<Eigen::Vector3d> project(const Eigen::Vector3d& x_in_world, int level) const;
};

// A view from a photo (CV_8UC3 BGR or CV_8U) and its mask (CV_8U at the
// photo's size, or empty: no mask). Throws InputError (naming `source`)
// when the photo's size differs from the camera's.
RefineView make_view(const Camera& camera,
                     const ImageRecord& pose,
                     const cv::Mat& photo,
                     int levels,
                     const std::string& source,
                     const cv::Mat& mask = cv::Mat());

// Every registered image of the workspace, with its mask when the workspace
// has one. Throws InputError naming an unreadable photo or mask.
std::vector<RefineView> load_views(const UndistortedWorkspace& workspace, int levels, Reporter& reporter);

// Renders the mesh's depth into every view at the size of pyramid level
// `level` (OpenMP over views).
void render_depths(const TriangleMesh& mesh, std::vector<RefineView>& views, int level);

// Scene units per pixel of level 0 at each vertex, in the view that resolves
// it finest among those it faces within max_incidence_deg, inside the image
// and in front of the camera (occlusion is not checked); +inf where no view
// does.
std::vector<float> pixel_footprints(const TriangleMesh& mesh,
                                    const std::vector<Eigen::Vector3f>& normals,
                                    const std::vector<RefineView>& views,
                                    double max_incidence_deg);

// Whether view sees x: in the image, in front of the camera, and no nearer
// than `tolerance` behind the depth buffer (over the 3x3 pixels around its
// projection, so a vertex on a silhouette still counts).
bool sees(const RefineView& view, const Eigen::Vector3d& x_in_world, double tolerance);

// The point of the current mesh seen at a pixel of the depth buffer's level
// (bilinear over four covered pixels); nothing where the pixel is not
// covered, or lies on a depth edge wider than max_depth_jump.
std::optional<Eigen::Vector3d> surface_point(const RefineView& view,
                                             const Eigen::Vector2d& pixel,
                                             double max_depth_jump);

// Whether the bilinear sample of pyramid level `level` whose top-left
// neighbour is pixel (x0, y0) may be used (RefineView::masks).
inline bool usable_sample(const RefineView& view, int level, int x0, int y0) {
  return view.masks.empty() || view.masks[level].at<unsigned char>(y0, x0) != 0;
}

// Bilinear grey level in [0, 1] of pyramid level `level` at a pixel (COLMAP
// convention); nothing outside the image or where the view is masked.
std::optional<float> sample(const RefineView& view, int level, const Eigen::Vector2d& pixel);

}  // namespace hos::refine
