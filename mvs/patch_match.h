// Per-view depth and normal estimation with PatchMatch stereo (Bleyer et al.
// 2011; multi-view form as in Galliani et al. 2015 and Schoenberger et al.
// 2016): every pixel holds a slanted plane (depth, normal); planes spread to
// neighbours by red-black checkerboard propagation and are refined by random
// perturbation; a plane's cost is the bilaterally weighted NCC of its window
// warped into each source view by the plane's homography, aggregated over the
// best K source views so occluded views do not ruin it.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/reporter.h"
#include "core/undistorted_workspace.h"
#include "mvs/mvs_options.h"

namespace hos::mvs {

// One image prepared for matching, at the matching scale. Pixel coordinates
// follow COLMAP: the centre of the top-left pixel is (0.5, 0.5).
struct MvsView {
  int image_id = 0;
  std::string name;
  cv::Mat gray;   // CV_32F in [0, 1]
  cv::Mat color;  // CV_8UC3, BGR
  // CV_8U at the view's size, kMaskedOut where the photo's mask excludes
  // the pixel (core/image_mask.h); empty: every pixel usable. A masked
  // pixel gets no depth, adds nothing to its neighbours' windows, and a
  // source whose masked pixel a window centre lands on does not count.
  cv::Mat mask;
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity(), K_inv = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // cam_from_world
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Vector3d center() const { return -R.transpose() * t; }
  int width() const { return gray.cols; }
  int height() const { return gray.rows; }
};

// Loads and downscales an image of the workspace, and its mask when the
// workspace has one. Throws InputError naming the file if it cannot be read
// or its size disagrees with its camera.
MvsView load_view(const UndistortedWorkspace& workspace, const ImageRecord& image, int max_image_size);

// Every pixel's plane at one level, reliable or not (a finer level starts
// from it): depth along the camera z axis, normal in the reference camera's
// frame, photometric cost (aggregated 1 - NCC; kTexturelessCost where
// textureless).
// The cost of a pixel too flat to be scored (2 is the worst cost of a
// scored one); depth maps keep it, so their readers can tell such pixels.
constexpr float kTexturelessCost = 3.0f;

struct PlaneMap {
  cv::Mat depth;                                    // CV_32F
  cv::Mat normal;                                   // CV_32FC3
  cv::Mat cost;                                     // CV_32F
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();  // of the level
};

// A neighbouring view's depth map at a coarser level, voting on the finer
// levels' geometry (multi-view geometric consistency, as in ACMM).
struct DepthPrior {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // cam_from_world
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  cv::Mat depth;  // CV_32F, 0 = no estimate
};

// A reference view's result; depth 0 marks pixels without a reliable estimate.
struct DepthMap {
  cv::Mat depth;   // CV_32F, camera z
  cv::Mat normal;  // CV_32FC3, world-frame unit normal facing the camera
  cv::Mat cost;    // CV_32F, aggregated 1 - NCC
};

struct PatchMatchStats {
  std::size_t valid_pixels = 0;
  std::size_t textureless_pixels = 0;
  std::size_t refined_pixels = 0;   // finer levels: pixels the sweeps revisited
  std::size_t restored_pixels = 0;  // finer levels: kept their own plane against the neighbours' vote
};

// The view at a smaller size (longest side at most max_image_size).
MvsView downscale_view(const MvsView& view, int max_image_size);

// Bytes a PatchMatch level holds per reference pixel (its planes, costs and
// precomputed windows), for memory estimates.
double matcher_bytes_per_pixel(const MvsOptions& options);

// Full PatchMatch (random initialisation, options.iterations sweeps of
// propagation and random refinement) of ref against sources within
// [depth_min, depth_max]; seed_points (world) are sparse points used to
// initialise nearby pixels.
PlaneMap match_planes(const MvsView& ref,
                      const std::vector<const MvsView*>& sources,
                      double depth_min,
                      double depth_max,
                      const std::vector<Eigen::Vector3d>& seed_points,
                      const MvsOptions& options,
                      Reporter& reporter);

// A finer level: coarse's planes upsampled to ref's size and refined with
// options.refine_iterations sweeps. Pixels whose upsampled plane matches
// well (cost at most options.refine_settled_cost) keep it; the others get
// propagation, perturbation and random planes. priors[s] (may be null) is
// source s's coarser depth map: a plane that disagrees with it pays up to
// options.geometric_weight per view (ACMM's geometric consistency), unless
// its own photometric cost beats the current plane's by
// options.detail_restore_margin (a thin structure the coarse maps missed).
PlaneMap refine_planes(const MvsView& ref,
                       const std::vector<const MvsView*>& sources,
                       const std::vector<const DepthPrior*>& priors,
                       const PlaneMap& coarse,
                       double depth_min,
                       double depth_max,
                       const std::vector<Eigen::Vector3d>& seed_points,
                       const MvsOptions& options,
                       Reporter& reporter,
                       PatchMatchStats* stats = nullptr);

// The reliable part of a plane map (cost at most options.max_cost, normals
// in the world frame).
DepthMap to_depth_map(const PlaneMap& planes,
                      const MvsView& ref,
                      const MvsOptions& options,
                      PatchMatchStats* stats = nullptr);

// Single-scale: to_depth_map(match_planes(...)).
DepthMap estimate_depth_map(const MvsView& ref,
                            const std::vector<const MvsView*>& sources,
                            double depth_min,
                            double depth_max,
                            const std::vector<Eigen::Vector3d>& seed_points,
                            const MvsOptions& options,
                            Reporter& reporter,
                            PatchMatchStats* stats = nullptr);

}  // namespace hos::mvs
