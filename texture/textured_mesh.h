// The result of texturing: geometry with per-vertex UVs, one index list per
// atlas page, the atlas images, and the root-node transform of the glTF.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

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
};

}  // namespace hos::texture
