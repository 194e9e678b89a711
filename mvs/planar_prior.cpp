#include "mvs/planar_prior.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace hos::mvs {
namespace {

struct Anchor {
  cv::Point2f pixel;       // image position of the pixel's centre
  Eigen::Vector3d point;   // camera frame
  Eigen::Vector3d normal;  // camera frame
};

// The lowest-cost pixel of each block, if it is confident.
std::vector<Anchor> confident_anchors(const PlaneMap& planes, double confident_cost, int block) {
  const Eigen::Matrix3d K_inv = planes.K.inverse();
  std::vector<Anchor> anchors;
  for (int by = 0; by < planes.depth.rows; by += block) {
    for (int bx = 0; bx < planes.depth.cols; bx += block) {
      int best_x = -1, best_y = -1;
      float best = static_cast<float>(confident_cost);
      for (int y = by; y < std::min(by + block, planes.depth.rows); ++y) {
        for (int x = bx; x < std::min(bx + block, planes.depth.cols); ++x) {
          const float c = planes.cost.at<float>(y, x);
          if (c <= best && planes.depth.at<float>(y, x) > 0) {
            best = c;
            best_x = x;
            best_y = y;
          }
        }
      }
      if (best_x < 0) continue;
      const cv::Vec3f n = planes.normal.at<cv::Vec3f>(best_y, best_x);
      const cv::Point2f pixel(best_x + 0.5f, best_y + 0.5f);
      anchors.push_back({pixel, K_inv * Eigen::Vector3d(pixel.x, pixel.y, 1.0) * planes.depth.at<float>(best_y, best_x),
                         Eigen::Vector3d(n[0], n[1], n[2]).normalized()});
    }
  }
  return anchors;
}

// The anchors' Delaunay triangles as index triples. Each block holds at
// most one anchor, so a vertex's block names it; the subdivision's outer
// corners lie outside the image and name none.
std::vector<cv::Vec3i> delaunay(const std::vector<Anchor>& anchors, cv::Size size, int block) {
  const int cols = (size.width + block - 1) / block, rows = (size.height + block - 1) / block;
  std::vector<int> anchor_of_block(static_cast<std::size_t>(cols) * rows, -1);
  cv::Subdiv2D subdiv(cv::Rect(0, 0, size.width + 1, size.height + 1));
  for (std::size_t i = 0; i < anchors.size(); ++i) {
    const cv::Point2f& p = anchors[i].pixel;
    anchor_of_block[static_cast<std::size_t>(p.y) / block * cols + static_cast<std::size_t>(p.x) / block] =
        static_cast<int>(i);
    subdiv.insert(p);
  }
  std::vector<cv::Vec6f> triangles;
  subdiv.getTriangleList(triangles);
  std::vector<cv::Vec3i> out;
  for (const cv::Vec6f& t : triangles) {
    cv::Vec3i ids;
    bool inside = true;
    for (int c = 0; c < 3 && inside; ++c) {
      const float x = t[2 * c], y = t[2 * c + 1];
      inside = x >= 0 && y >= 0 && x < float(size.width) && y < float(size.height);
      if (inside)
        ids[c] = anchor_of_block[static_cast<std::size_t>(y) / block * cols + static_cast<std::size_t>(x) / block];
      inside = inside && ids[c] >= 0;
    }
    if (inside) out.push_back(ids);
  }
  return out;
}

// Writes the plane of triangle t into every pixel whose centre it covers.
void rasterise(const std::vector<Anchor>& a,
               const cv::Vec3i& t,
               const Eigen::Vector3d& n,
               const Eigen::Matrix3d& K_inv,
               PriorPlanes& out) {
  const cv::Point2f p[3] = {a[t[0]].pixel, a[t[1]].pixel, a[t[2]].pixel};
  const double area = (p[1] - p[0]).cross(p[2] - p[0]);
  if (std::abs(area) < 1e-9) return;
  const double offset = n.dot(a[t[0]].point);
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].x, p[1].x, p[2].x}))));
  const int x1 = std::min(out.depth.cols - 1, static_cast<int>(std::ceil(std::max({p[0].x, p[1].x, p[2].x}))));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].y, p[1].y, p[2].y}))));
  const int y1 = std::min(out.depth.rows - 1, static_cast<int>(std::ceil(std::max({p[0].y, p[1].y, p[2].y}))));
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const cv::Point2f s(x + 0.5f, y + 0.5f);
      bool inside = true;
      for (int c = 0; c < 3 && inside; ++c) inside = (p[(c + 1) % 3] - p[c]).cross(s - p[c]) * area >= 0;
      if (!inside) continue;
      const Eigen::Vector3d ray = K_inv * Eigen::Vector3d(s.x, s.y, 1.0);
      const double depth = offset / n.dot(ray);
      if (!(depth > 0)) continue;
      out.depth.at<float>(y, x) = static_cast<float>(depth);
      out.normal.at<cv::Vec3f>(y, x) = cv::Vec3f(float(n.x()), float(n.y()), float(n.z()));
    }
  }
}

}  // namespace

PriorPlanes planar_prior(const PlaneMap& planes, double confident_cost, int block_px, double max_normal_deviation_deg) {
  PriorPlanes out{cv::Mat::zeros(planes.depth.size(), CV_32F), cv::Mat::zeros(planes.depth.size(), CV_32FC3)};
  const std::vector<Anchor> anchors = confident_anchors(planes, confident_cost, block_px);
  if (anchors.size() < 3) return out;
  const Eigen::Matrix3d K_inv = planes.K.inverse();
  const double cos_deviation = std::cos(max_normal_deviation_deg * M_PI / 180.0);
  const double cos_edge_on = std::cos(85.0 * M_PI / 180.0);
  for (const cv::Vec3i& t : delaunay(anchors, planes.depth.size(), block_px)) {
    const Eigen::Vector3d& a = anchors[t[0]].point;
    Eigen::Vector3d n = (anchors[t[1]].point - a).cross(anchors[t[2]].point - a);
    if (!(n.norm() > 0)) continue;
    n.normalize();
    if (n.dot(a) > 0) n = -n;  // towards the camera
    bool planar = true;
    for (int c = 0; c < 3 && planar; ++c) planar = std::abs(n.dot(anchors[t[c]].normal)) >= cos_deviation;
    if (!planar || -n.dot(a.normalized()) < cos_edge_on) continue;
    rasterise(anchors, t, n, K_inv, out);
  }
  return out;
}

}  // namespace hos::mvs
