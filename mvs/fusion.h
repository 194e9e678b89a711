// Geometric consistency and fusion of depth maps into one oriented point set.
// A pixel survives when at least min_consistent_views other views agree with
// it: its 3D point projects onto a pixel of the other view whose depth is
// within max_depth_error (relative), whose normal is within
// max_normal_error_deg, and whose own point projects back within
// max_reprojection_error_px. Agreeing views count only from distinct
// viewpoints (min_triangulation_angle_deg apart at the point); a point that
// exactly two such views agree on survives under the two_view_* rules (the
// other views that cover it, and face its surface within
// two_view_veto_max_incidence_deg, must have a depth there).
// Agreeing pixels are merged into one point (averaged position, normal and
// colour) and marked used, so every surface point is emitted once; the number
// of distinct agreeing viewpoints is its confidence. Density control: a
// point also claims its pixels' neighbours within fusion_spacing_px that lie
// on the same surface, so at photo resolution a surface gets one point per
// few pixels rather than one per pixel.
#pragma once

#include <vector>

#include "core/reporter.h"
#include "core/types.h"
#include "mvs/mvs_options.h"
#include "mvs/patch_match.h"

namespace hos::mvs {

// A unit normal in two 16-bit octahedral coordinates (the octant's face
// unfolded onto a square), within 0.01 degrees of the normal; zero decodes
// to some unit vector.
cv::Vec2s encode_normal(const Eigen::Vector3d& n);
Eigen::Vector3d decode_normal(cv::Vec2s code);

// A depth map as fusion keeps it: 10 bytes a pixel instead of DepthMap's 20,
// so photo-resolution maps of many views fit.
struct FusionMap {
  cv::Mat depth;   // CV_32F, camera z, 0 = no estimate
  cv::Mat normal;  // CV_16SC2, encode_normal of the world-frame normal
  cv::Mat cost;    // CV_16F, aggregated 1 - NCC
  FusionMap() = default;
  explicit FusionMap(const DepthMap& map);
};

// Bytes fusion keeps per pixel of every view: the FusionMap and the colour.
double fusion_bytes_per_pixel();

// The parts of a view fusion needs (its image is not).
struct FusionView {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity(), K_inv = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  FusionMap map;
  cv::Mat color;  // CV_8UC3 at the depth map's size
};

FusionView make_fusion_view(const MvsView& view, const DepthMap& map);

class FusionViewStore;

// Fuses every view of the store: each reference view's pixels are checked
// against the views neighbours[r] lists (indices into the store, the views
// that overlap it), with only those views' maps held in memory.
PointCloud fuse_depth_maps(FusionViewStore& views,
                           const std::vector<std::vector<std::size_t>>& neighbours,
                           const MvsOptions& options,
                           Reporter& reporter);

// All views in memory, each checked against every other.
PointCloud fuse_depth_maps(const std::vector<FusionView>& views, const MvsOptions& options, Reporter& reporter);

}  // namespace hos::mvs
