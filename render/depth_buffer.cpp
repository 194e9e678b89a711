#include "render/depth_buffer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/scan_triangle.h"

namespace hos::render {
DepthBuffer rasterize_depth(const TriangleMesh& mesh,
                            const std::vector<Eigen::Vector3f>& projected,
                            int width,
                            int height) {
  DepthBuffer buffer;
  buffer.depth = cv::Mat(height, width, CV_32F, cv::Scalar(std::numeric_limits<float>::infinity()));
  buffer.face_id = cv::Mat(height, width, CV_32S, cv::Scalar(-1));
  for (int f = 0; f < static_cast<int>(mesh.faces.size()); ++f) {
    const auto& face = mesh.faces[f];
    const Eigen::Vector3f& a = projected[face[0]];
    const Eigen::Vector3f& b = projected[face[1]];
    const Eigen::Vector3f& c = projected[face[2]];
    // A face crossing the camera plane has no affine image; such faces are
    // rare and hide little that a view can use.
    if (a.z() <= kMinDepth || b.z() <= kMinDepth || c.z() <= kMinDepth) continue;
    const float area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    if (area == 0.0f || !std::isfinite(area)) continue;
    const PixelRange range{std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}) - 0.5f))),
                           std::min(width - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}) - 0.5f))),
                           std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}) - 0.5f))),
                           std::min(height - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}) - 0.5f)))};
    const float iza = 1.0f / a.z(), izb = 1.0f / b.z(), izc = 1.0f / c.z();
    scan_triangle(a, b, c, 1.0f / area, range, [&](int x, int y, float wa, float wb, float wc) {
      // 1/z is affine in screen space.
      const float z = 1.0f / (wa * iza + wb * izb + wc * izc);
      float& depth = buffer.depth.at<float>(y, x);
      if (z < depth) {
        depth = z;
        buffer.face_id.at<int>(y, x) = f;
      }
    });
  }
  return buffer;
}

}  // namespace hos::render
