#include "mvs/fusion.h"

#include <cmath>

namespace hos::mvs {
namespace {

struct Observation {
  int view;
  int x, y;
  Eigen::Vector3d point;
  Eigen::Vector3d normal;
};

// The agreeing views of one reference pixel, and how many other views cover
// its point (in front, inside the image) without a depth there.
struct Agreement {
  std::vector<Observation> observations;
  int views_without_depth = 0;
};

Eigen::Vector3d back_project(const FusionView& v, int x, int y, double depth) {
  const Eigen::Vector3d xc = v.K_inv * Eigen::Vector3d(x + 0.5, y + 0.5, 1.0) * depth;
  return v.R.transpose() * (xc - v.t);
}

Eigen::Vector3d normal_at(const FusionView& v, int x, int y) {
  const cv::Vec3f n = v.map.normal.at<cv::Vec3f>(y, x);
  return Eigen::Vector3d(n[0], n[1], n[2]);
}

}  // namespace

FusionView make_fusion_view(const MvsView& view, DepthMap map) {
  FusionView f;
  f.K = view.K;
  f.K_inv = view.K_inv;
  f.R = view.R;
  f.t = view.t;
  f.map = std::move(map);
  f.color = view.color;
  return f;
}

PointCloud fuse_depth_maps(const std::vector<FusionView>& views, const MvsOptions& options, Reporter& reporter) {
  const double cos_normal = std::cos(options.max_normal_error_deg * M_PI / 180.0);
  const double max_reproj2 = options.max_reprojection_error_px * options.max_reprojection_error_px;
  const double cos_triangulation = std::cos(options.min_triangulation_angle_deg * M_PI / 180.0);
  std::vector<Eigen::Vector3d> centres;
  for (const auto& v : views) centres.push_back(v.R.transpose() * -v.t);
  // Views that saw the point from distinct viewpoints (the reference first):
  // an agreeing view whose ray makes less than the triangulation angle with
  // a counted one is merged but is no further evidence, as with two photos
  // taken from the same spot, which agree on any depth.
  const auto independent_views = [&](const std::vector<Observation>& obs) {
    std::vector<Eigen::Vector3d> rays;
    for (const auto& o : obs) {
      const Eigen::Vector3d ray = (centres[o.view] - o.point).normalized();
      bool distinct = true;
      for (const auto& q : rays) distinct = distinct && ray.dot(q) < cos_triangulation;
      if (distinct) rays.push_back(ray);
    }
    return static_cast<int>(rays.size());
  };
  // A point two independent views agree on is kept when both pixels matched
  // well and every other view that covers it has a depth there: a view that
  // sees nothing matchable at that spot (background, a gap between parts of
  // the object) speaks against the point.
  const auto reliable_two_view = [&](const Agreement& a) {
    if (options.two_view_max_cost <= 0.0 || a.views_without_depth > options.two_view_max_views_without_depth) {
      return false;
    }
    for (const auto& o : a.observations) {
      if (!(views[o.view].map.cost.at<float>(o.y, o.x) <= options.two_view_max_cost)) return false;
    }
    return true;
  };
  std::vector<cv::Mat> used;
  for (const auto& v : views) used.push_back(cv::Mat::zeros(v.map.depth.size(), CV_8U));
  PointCloud cloud;
  reporter.begin("fusion", static_cast<std::int64_t>(views.size()));
  for (std::size_t r = 0; r < views.size(); ++r) {
    reporter.throw_if_cancelled();
    const FusionView& ref = views[r];
    const int w = ref.map.depth.cols, h = ref.map.depth.rows;
    std::vector<std::vector<Agreement>> rows(h);
    // Consistency checks in parallel; merging and marking in order below.
#pragma omp parallel for schedule(dynamic, 4)
    for (int y = 0; y < h; ++y) {
      rows[y].resize(w);
      for (int x = 0; x < w; ++x) {
        const float d = ref.map.depth.at<float>(y, x);
        if (!(d > 0) || used[r].at<uchar>(y, x)) continue;
        const Eigen::Vector3d X = back_project(ref, x, y, d);
        const Eigen::Vector3d n = normal_at(ref, x, y);
        Agreement& agreement = rows[y][x];
        auto& obs = agreement.observations;
        obs.push_back({static_cast<int>(r), x, y, X, n});
        for (std::size_t s = 0; s < views.size(); ++s) {
          if (s == r) continue;
          const FusionView& src = views[s];
          const Eigen::Vector3d xs = src.R * X + src.t;
          if (xs.z() <= 0) continue;
          const Eigen::Vector3d uv = src.K * xs / xs.z();
          const int qx = static_cast<int>(std::floor(uv.x())), qy = static_cast<int>(std::floor(uv.y()));
          if (qx < 0 || qy < 0 || qx >= src.map.depth.cols || qy >= src.map.depth.rows) continue;
          const float ds = src.map.depth.at<float>(qy, qx);
          if (!(ds > 0)) ++agreement.views_without_depth;
          if (!(ds > 0) || used[s].at<uchar>(qy, qx)) continue;
          if (std::abs(xs.z() - ds) > options.max_depth_error * ds) continue;
          const Eigen::Vector3d ns = normal_at(src, qx, qy);
          if (ns.dot(n) < cos_normal) continue;
          const Eigen::Vector3d Xs = back_project(src, qx, qy, ds);
          const Eigen::Vector3d back = ref.R * Xs + ref.t;
          if (back.z() <= 0) continue;
          const Eigen::Vector3d buv = ref.K * back / back.z();
          if ((buv.head<2>() - Eigen::Vector2d(x + 0.5, y + 0.5)).squaredNorm() > max_reproj2) continue;
          obs.push_back({static_cast<int>(s), qx, qy, Xs, ns});
        }
      }
    }
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const auto& obs = rows[y][x].observations;
        if (obs.size() < 2) continue;
        const int independent = independent_views(obs);
        if (independent < options.min_consistent_views + 1 && !(independent == 2 && reliable_two_view(rows[y][x]))) {
          continue;
        }
        // Pixels claimed by an earlier point of this view in this pass.
        bool taken = false;
        for (const auto& o : obs) taken = taken || used[o.view].at<uchar>(o.y, o.x);
        if (taken) continue;
        Eigen::Vector3d p = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::Zero(), c = Eigen::Vector3d::Zero();
        for (const auto& o : obs) {
          p += o.point;
          n += o.normal;
          const cv::Vec3b bgr = views[o.view].color.at<cv::Vec3b>(o.y, o.x);
          c += Eigen::Vector3d(bgr[2], bgr[1], bgr[0]);
          used[o.view].at<uchar>(o.y, o.x) = 1;
        }
        const double k = static_cast<double>(obs.size());
        p /= k;
        c /= k;
        if (n.norm() < 1e-9) continue;
        n.normalize();
        // Normals point towards the cameras that saw the point.
        if (n.dot(ref.R.transpose() * (-ref.t) - p) < 0) n = -n;
        cloud.positions.push_back(p.cast<float>());
        cloud.normals.push_back(n.cast<float>());
        cloud.colors.push_back({static_cast<std::uint8_t>(std::lround(c.x())),
                                static_cast<std::uint8_t>(std::lround(c.y())),
                                static_cast<std::uint8_t>(std::lround(c.z()))});
        cloud.confidence.push_back(static_cast<float>(independent));
      }
    }
    reporter.advance();
  }
  reporter.end();
  return cloud;
}

}  // namespace hos::mvs
