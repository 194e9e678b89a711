#include "mvs/fusion.h"

#include <algorithm>
#include <cmath>

#include "mvs/fusion_store.h"

namespace hos::mvs {
namespace {

struct Observation {
  int view;
  int x, y;
  Eigen::Vector3d point;
  Eigen::Vector3d normal;
};

// The agreeing views of one reference pixel, and how many other views cover
// its point (in front, inside the image) without a depth there while facing
// its surface within the veto's incidence.
struct Agreement {
  std::vector<Observation> observations;
  int views_without_depth = 0;
};

Eigen::Vector3d back_project(const FusionView& v, int x, int y, double depth) {
  const Eigen::Vector3d xc = v.K_inv * Eigen::Vector3d(x + 0.5, y + 0.5, 1.0) * depth;
  return v.R.transpose() * (xc - v.t);
}

Eigen::Vector3d normal_at(const FusionView& v, int x, int y) { return decode_normal(v.map.normal.at<cv::Vec2s>(y, x)); }

// The depth at the exact image point uv of the plane of pixel (x, y) of v
// (its depth and world normal): sampling the pixel's own depth instead errs
// by up to d tan(incidence) / f per pixel of rounding, which at the incidence
// of ground seen from standing height (75-85 degrees) exceeds
// max_depth_error. The pixel's depth where the plane is seen too grazingly
// for the intersection to be stable.
double plane_depth(
    const FusionView& v, int x, int y, double depth, const Eigen::Vector3d& normal, const Eigen::Vector2d& uv) {
  const Eigen::Vector3d n = v.R * normal;
  const Eigen::Vector3d on_plane = v.K_inv * Eigen::Vector3d(x + 0.5, y + 0.5, 1.0) * depth;
  const Eigen::Vector3d ray = v.K_inv * Eigen::Vector3d(uv.x(), uv.y(), 1.0);
  const double denom = n.dot(ray);
  if (std::abs(denom) < 0.05 * ray.norm()) return depth;
  const double d = n.dot(on_plane) / denom;
  return d > 0 ? d : depth;
}

float cost_at(const FusionView& v, int x, int y) { return float(v.map.cost.at<cv::float16_t>(y, x)); }

// The folding of the octahedron's lower half onto the square's corners.
Eigen::Vector2d fold(const Eigen::Vector2d& p) {
  return {(1.0 - std::abs(p.y())) * (p.x() >= 0 ? 1.0 : -1.0), (1.0 - std::abs(p.x())) * (p.y() >= 0 ? 1.0 : -1.0)};
}

}  // namespace

cv::Vec2s encode_normal(const Eigen::Vector3d& n) {
  const double l1 = n.cwiseAbs().sum();
  if (!(l1 > 0)) return {0, 0};
  Eigen::Vector2d p = n.head<2>() / l1;
  if (n.z() < 0) p = fold(p);
  return {static_cast<short>(std::lround(p.x() * 32767.0)), static_cast<short>(std::lround(p.y() * 32767.0))};
}

Eigen::Vector3d decode_normal(cv::Vec2s code) {
  Eigen::Vector2d p(code[0] / 32767.0, code[1] / 32767.0);
  const double z = 1.0 - p.cwiseAbs().sum();
  if (z < 0) p = fold(p);
  return Eigen::Vector3d(p.x(), p.y(), z).normalized();
}

FusionMap::FusionMap(const DepthMap& map) : depth(map.depth), normal(map.normal.size(), CV_16SC2) {
  for (int y = 0; y < map.normal.rows; ++y) {
    for (int x = 0; x < map.normal.cols; ++x) {
      const cv::Vec3f n = map.normal.at<cv::Vec3f>(y, x);
      normal.at<cv::Vec2s>(y, x) = encode_normal(Eigen::Vector3d(n[0], n[1], n[2]));
    }
  }
  map.cost.convertTo(cost, CV_16F);
}

double fusion_bytes_per_pixel() {
  return sizeof(float) + sizeof(cv::Vec2s) + sizeof(cv::float16_t) + sizeof(cv::Vec3b);
}

FusionView make_fusion_view(const MvsView& view, const DepthMap& map) {
  FusionView f;
  f.K = view.K;
  f.K_inv = view.K_inv;
  f.R = view.R;
  f.t = view.t;
  f.map = FusionMap(map);
  f.color = view.color;
  return f;
}

namespace {

// The fixed parts of the rules, and the views' centres.
struct FusionRules {
  const MvsOptions& options;
  double cos_normal, max_reproj2, cos_triangulation, cos_veto_incidence;
  std::vector<Eigen::Vector3d> centres;
  FusionRules(const FusionViewStore& views, const MvsOptions& o)
      : options(o),
        cos_normal(std::cos(o.max_normal_error_deg * M_PI / 180.0)),
        max_reproj2(o.max_reprojection_error_px * o.max_reprojection_error_px),
        cos_triangulation(std::cos(o.min_triangulation_angle_deg * M_PI / 180.0)),
        cos_veto_incidence(std::cos(o.two_view_veto_max_incidence_deg * M_PI / 180.0)) {
    for (std::size_t i = 0; i < views.size(); ++i) centres.push_back(views[i].R.transpose() * -views[i].t);
  }
};

// The reference pixel's point and every unused pixel of a neighbouring view
// that agrees with it on depth, normal and forward-backward reprojection.
Agreement agreeing_pixels(const FusionViewStore& views,
                          const std::vector<std::size_t>& neighbours,
                          const std::vector<cv::Mat>& used,
                          const FusionRules& rules,
                          std::size_t r,
                          int x,
                          int y) {
  Agreement agreement;
  const FusionView& ref = views[r];
  const float d = ref.map.depth.at<float>(y, x);
  if (!(d > 0) || used[r].at<uchar>(y, x)) return agreement;
  const Eigen::Vector3d X = back_project(ref, x, y, d);
  const Eigen::Vector3d n = normal_at(ref, x, y);
  auto& obs = agreement.observations;
  obs.push_back({static_cast<int>(r), x, y, X, n});
  for (std::size_t s : neighbours) {
    const FusionView& src = views[s];
    const Eigen::Vector3d xs = src.R * X + src.t;
    if (xs.z() <= 0) continue;
    const Eigen::Vector3d uv = src.K * xs / xs.z();
    const int qx = static_cast<int>(std::floor(uv.x())), qy = static_cast<int>(std::floor(uv.y()));
    if (qx < 0 || qy < 0 || qx >= src.map.depth.cols || qy >= src.map.depth.rows) continue;
    const float ds = src.map.depth.at<float>(qy, qx);
    if (!(ds > 0) && n.dot((rules.centres[s] - X).normalized()) >= rules.cos_veto_incidence)
      ++agreement.views_without_depth;
    if (!(ds > 0) || used[s].at<uchar>(qy, qx)) continue;
    const Eigen::Vector3d ns = normal_at(src, qx, qy);
    const double d_plane = plane_depth(src, qx, qy, ds, ns, uv.head<2>());
    if (std::abs(xs.z() - d_plane) > rules.options.max_depth_error * d_plane) continue;
    if (ns.dot(n) < rules.cos_normal) continue;
    const Eigen::Vector3d Xs = src.R.transpose() * (src.K_inv * uv * d_plane - src.t);
    const Eigen::Vector3d back = ref.R * Xs + ref.t;
    if (back.z() <= 0) continue;
    const Eigen::Vector3d buv = ref.K * back / back.z();
    if ((buv.head<2>() - Eigen::Vector2d(x + 0.5, y + 0.5)).squaredNorm() > rules.max_reproj2) continue;
    obs.push_back({static_cast<int>(s), qx, qy, Xs, ns});
  }
  return agreement;
}

// Views that saw the point from distinct viewpoints (the reference first):
// an agreeing view whose ray makes less than the triangulation angle with a
// counted one is merged but is no further evidence, as with two photos taken
// from the same spot, which agree on any depth.
int independent_views(const std::vector<Observation>& obs, const FusionRules& rules) {
  std::vector<Eigen::Vector3d> rays;
  for (const auto& o : obs) {
    const Eigen::Vector3d ray = (rules.centres[o.view] - o.point).normalized();
    bool distinct = true;
    for (const auto& q : rays) distinct = distinct && ray.dot(q) < rules.cos_triangulation;
    if (distinct) rays.push_back(ray);
  }
  return static_cast<int>(rays.size());
}

// A point two independent views agree on is kept when both pixels matched
// well and every other view that covers it has a depth there: a view that
// sees nothing matchable at that spot (background, a gap between parts of
// the object) speaks against the point.
bool reliable_two_view(const FusionViewStore& views, const Agreement& a, const FusionRules& rules) {
  const MvsOptions& o = rules.options;
  if (o.two_view_max_cost <= 0.0 || a.views_without_depth > o.two_view_max_views_without_depth) return false;
  for (const auto& obs : a.observations) {
    if (!(cost_at(views[obs.view], obs.x, obs.y) <= o.two_view_max_cost)) return false;
  }
  return true;
}

// The agreeing pixels' mean position, normal (towards the reference
// camera) and colour; false if the normals cancel.
bool merge(const FusionViewStore& views,
           const std::vector<Observation>& obs,
           const Eigen::Vector3d& ref_centre,
           PointCloud& cloud) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::Zero(), c = Eigen::Vector3d::Zero();
  for (const auto& o : obs) {
    p += o.point;
    n += o.normal;
    const cv::Vec3b bgr = views[o.view].color.at<cv::Vec3b>(o.y, o.x);
    c += Eigen::Vector3d(bgr[2], bgr[1], bgr[0]);
  }
  const double k = static_cast<double>(obs.size());
  p /= k;
  c /= k;
  if (n.norm() < 1e-9) return false;
  n.normalize();
  if (n.dot(ref_centre - p) < 0) n = -n;
  cloud.positions.push_back(p.cast<float>());
  cloud.normals.push_back(n.cast<float>());
  cloud.colors.push_back({static_cast<std::uint8_t>(std::lround(c.x())), static_cast<std::uint8_t>(std::lround(c.y())),
                          static_cast<std::uint8_t>(std::lround(c.z()))});
  return true;
}

// Marks the merged pixels used, and (density control) their neighbours
// within fusion_spacing_px on the same surface (depth within
// max_depth_error), so no other point is made there.
void claim(const FusionViewStore& views,
           const std::vector<Observation>& obs,
           const MvsOptions& options,
           std::vector<cv::Mat>& used) {
  const int r = options.fusion_spacing_px;
  for (const auto& o : obs) {
    cv::Mat& mask = used[o.view];
    const cv::Mat& depth = views[o.view].map.depth;
    const float d = depth.at<float>(o.y, o.x);
    mask.at<uchar>(o.y, o.x) = 1;
    for (int y = std::max(0, o.y - r); y <= std::min(depth.rows - 1, o.y + r); ++y) {
      for (int x = std::max(0, o.x - r); x <= std::min(depth.cols - 1, o.x + r); ++x) {
        if (std::abs(depth.at<float>(y, x) - d) <= options.max_depth_error * d) mask.at<uchar>(y, x) = 1;
      }
    }
  }
}

// Keeps the agreement of one reference pixel as a point if enough
// independent views agree and none of its pixels is claimed yet.
void fuse_pixel(const FusionViewStore& views,
                const Agreement& agreement,
                const FusionRules& rules,
                std::size_t r,
                std::vector<cv::Mat>& used,
                PointCloud& cloud) {
  const auto& obs = agreement.observations;
  if (obs.size() < 2) return;
  const int independent = independent_views(obs, rules);
  if (independent < rules.options.min_consistent_views + 1 &&
      !(independent == 2 && reliable_two_view(views, agreement, rules))) {
    return;
  }
  for (const auto& o : obs) {
    if (used[o.view].at<uchar>(o.y, o.x)) return;
  }
  claim(views, obs, rules.options, used);
  if (merge(views, obs, rules.centres[r], cloud)) cloud.confidence.push_back(static_cast<float>(independent));
}

}  // namespace

PointCloud fuse_depth_maps(FusionViewStore& views,
                           const std::vector<std::vector<std::size_t>>& neighbours,
                           const MvsOptions& options,
                           Reporter& reporter) {
  const FusionRules rules(views, options);
  std::vector<cv::Mat> used;
  used.reserve(views.size());
  for (std::size_t i = 0; i < views.size(); ++i) used.push_back(cv::Mat::zeros(views.map_size(i), CV_8U));
  PointCloud cloud;
  reporter.begin("fusion", static_cast<std::int64_t>(views.size()));
  for (std::size_t r = 0; r < views.size(); ++r) {
    reporter.throw_if_cancelled();
    // Ascending, so that the observations' order (and the merged sums) do
    // not depend on how the neighbours were ranked.
    std::vector<std::size_t> others = neighbours[r];
    std::sort(others.begin(), others.end());
    std::vector<std::size_t> held = others;
    held.push_back(r);
    views.hold(held);
    const int w = views[r].map.depth.cols, h = views[r].map.depth.rows;
    // Blocks of rows: consistency checks in parallel, then merging and
    // marking in order (which the next block's checks see); only a block's
    // agreements are in memory.
    constexpr int kBlockRows = 16;
    std::vector<std::vector<Agreement>> rows(kBlockRows, std::vector<Agreement>(w));
    for (int y0 = 0; y0 < h; y0 += kBlockRows) {
      const int y1 = std::min(h, y0 + kBlockRows);
#pragma omp parallel for schedule(dynamic, 1)
      for (int y = y0; y < y1; ++y) {
        for (int x = 0; x < w; ++x) rows[y - y0][x] = agreeing_pixels(views, others, used, rules, r, x, y);
      }
      for (int y = y0; y < y1; ++y) {
        for (int x = 0; x < w; ++x) fuse_pixel(views, rows[y - y0][x], rules, r, used, cloud);
      }
    }
    reporter.advance();
  }
  reporter.end();
  return cloud;
}

PointCloud fuse_depth_maps(const std::vector<FusionView>& views, const MvsOptions& options, Reporter& reporter) {
  FusionViewStore store(0, {});
  std::vector<std::vector<std::size_t>> neighbours(views.size());
  for (std::size_t r = 0; r < views.size(); ++r) {
    store.add(views[r]);
    for (std::size_t s = 0; s < views.size(); ++s) {
      if (s != r) neighbours[r].push_back(s);
    }
  }
  return fuse_depth_maps(store, neighbours, options, reporter);
}

}  // namespace hos::mvs
