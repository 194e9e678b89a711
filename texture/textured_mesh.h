// The result of texturing: geometry with per-vertex UVs, one index list per
// atlas page, the atlas images, and the root-node transform of the glTF.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "core/geodesy.h"

namespace hos::texture {

struct TexturedMesh {
  std::vector<Eigen::Vector3f> positions;  // SfM model coordinates
  std::vector<Eigen::Vector3f> normals;    // unit
  std::vector<Eigen::Vector2f> uvs;        // glTF: u right, v down from the top-left
  // Triangles (counter-clockwise from outside) of each atlas page.
  std::vector<std::vector<std::uint32_t>> indices;
  std::vector<cv::Mat> atlases;  // CV_8UC3, BGR
  // Column-major in glTF; maps model coordinates to the viewer's frame.
  Eigen::Matrix4d root_matrix = Eigen::Matrix4d::Identity();
  // The root frame's units are metres (GPS or a measured distance), and
  // where its origin is on Earth (GPS); written into the glTF's asset.extras.
  bool metric = false;
  std::optional<GeoPosition> geo_origin;
};

}  // namespace hos::texture
