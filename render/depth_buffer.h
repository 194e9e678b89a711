// The nearest surface at every pixel centre, depth and face only: the
// visibility buffers of texture and refine, which need no colour, lighting
// or supersampling (render_view's cost at photo resolution).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "core/types.h"

namespace hos::render {

// Nearer than this (camera z), a vertex counts as at or behind the camera.
constexpr float kMinDepth = 1e-6f;

struct DepthBuffer {
  cv::Mat depth;    // CV_32F camera z of the nearest surface, +inf where empty
  cv::Mat face_id;  // CV_32S index into mesh.faces, -1 where empty
};

// projected[i] is vertex i in the image: continuous pixel x, y (the centre of
// the top-left pixel at (0.5, 0.5)) and camera depth z. Faces with a corner
// at z <= kMinDepth (crossing or behind the camera) or of zero or non-finite
// area are skipped. The buffers are width x height.
DepthBuffer rasterize_depth(const TriangleMesh& mesh,
                            const std::vector<Eigen::Vector3f>& projected,
                            int width,
                            int height);

}  // namespace hos::render
