#include "mvs/patch_match.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "core/cpu_clones.h"
#include "core/error.h"
#include "core/image_mask.h"
#include "mvs/planar_prior.h"
#include "mvs/window_ncc.h"

namespace hos::mvs {
namespace {

// Deterministic per-(pixel, iteration, draw) random numbers, so results do
// not depend on the number of threads.
double random_unit(std::uint64_t seed) {
  seed += 0x9E3779B97F4A7C15ull;
  seed = (seed ^ (seed >> 30)) * 0xBF58476D1CE4E5B9ull;
  seed = (seed ^ (seed >> 27)) * 0x94D049BB133111EBull;
  seed ^= seed >> 31;
  return static_cast<double>(seed >> 11) * (1.0 / 9007199254740992.0);
}

struct Plane {
  float depth = 0.0f;
  Eigen::Vector3f normal = Eigen::Vector3f(0, 0, -1);  // reference camera frame
};

// A plane's cost: the photometric part (mean 1 - NCC of the best K views)
// and the one planes compete on, which adds the neighbours' geometric vote
// capped at the detail restoration margin (so a plane whose photometric
// cost is better by more than the margin wins against the vote).
struct Cost {
  float effective = 2.0f;
  float photo = 2.0f;
};

// A source view's coarser depth map relative to the reference camera.
struct PriorFrame {
  const DepthPrior* prior = nullptr;
  Eigen::Matrix3f R;  // prior_cam_from_ref_cam
  Eigen::Vector3f t;
  Eigen::Matrix3f K, K_inv;
  Eigen::Matrix3f R_back;  // ref_cam_from_prior_cam
  Eigen::Vector3f t_back;
};

// A masked-out pixel of the view's mask (core/image_mask.h); none without one.
bool masked(const MvsView& view, int x, int y) {
  return !view.mask.empty() && view.mask.at<unsigned char>(y, x) == kMaskedOut;
}

class PatchMatcher {
 public:
  PatchMatcher(const MvsView& ref,
               const std::vector<const MvsView*>& sources,
               double depth_min,
               double depth_max,
               const MvsOptions& options,
               const std::vector<const DepthPrior*>& priors = {})
      : ref_(ref), sources_(sources), options_(options), inv_min_(1.0 / depth_max), inv_max_(1.0 / depth_min) {
    for (int dy = -options.window_radius; dy <= options.window_radius; dy += options.window_step) {
      for (int dx = -options.window_radius; dx <= options.window_radius; dx += options.window_step) {
        offsets_.emplace_back(dx, dy);
        offset_x_.push_back(float(dx));
        offset_y_.push_back(float(dy));
      }
    }
    // Padded for the kernel's eight lanes (mvs/window_ncc.h).
    while (offset_x_.size() % kNccLanes != 0) {
      offset_x_.push_back(0.0f);
      offset_y_.push_back(0.0f);
    }
    window_.offset_x = offset_x_.data();
    window_.offset_y = offset_y_.data();
    window_.count = static_cast<int>(offsets_.size());
    window_.low = float(-options.window_radius);
    // The last sample's offset: the window's width floored to whole steps.
    const int last_offset =
        2 * options.window_radius / options.window_step * options.window_step - options.window_radius;
    window_.high = float(last_offset);
    for (const MvsView* s : sources) {
      source_quads_.push_back(make_quad_image(s->gray));
      const Eigen::Matrix3d r_rel = s->R * ref.R.transpose();
      const Eigen::Vector3d t_rel = s->t - r_rel * ref.t;
      relative_.push_back({(s->K * r_rel * ref.K_inv).cast<float>(), (s->K * t_rel).cast<float>()});
    }
    prepare_propagation_areas();
    prepare_priors(priors);
    const int w = ref.width(), h = ref.height();
    planes_.resize(std::size_t(w) * h);
    costs_.assign(std::size_t(w) * h, 2.0f);
    photo_.assign(std::size_t(w) * h, 2.0f);
    changed_.assign(std::size_t(w) * h, -1);
    settled_.assign(std::size_t(w) * h, 0);
    inherited_.assign(std::size_t(w) * h, kTexturelessCost);
    const int nsrc = static_cast<int>(std::min<std::size_t>(sources.size(), 32));
    views_.assign(std::size_t(w) * h, nsrc == 32 ? ~0u : (1u << nsrc) - 1u);
    reselect_.assign(std::size_t(w) * h, 1);
    prepare_windows();
  }

  // Coarsest level: random planes, the sparse points' depths where they project.
  void initialise(const std::vector<Eigen::Vector3d>& seeds) {
    const int w = ref_.width(), h = ref_.height();
#pragma omp parallel for schedule(dynamic, 4)
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t i = std::size_t(y) * w + x;
        planes_[i] = random_plane(x, y, i * 7919u);
      }
    }
    for_seed_pixels(seeds, [&](int x, int y, const Plane& seed) { planes_[std::size_t(y) * w + x] = seed; });
    score_all();
  }

  // Finer level: each pixel starts from the plane of the coarse pixel it
  // lies in, re-intersected with its own ray; pixels where that plane
  // matches well are settled and left alone by the sweeps, and pixels too
  // flat at this level to be scored keep it with the coarse pixel's cost.
  void initialise_from(const PlaneMap& coarse, const std::vector<Eigen::Vector3d>& seeds) {
    const int w = ref_.width(), h = ref_.height();
    const Eigen::Matrix3d coarse_K_inv = coarse.K.inverse();
    const double sx = double(coarse.depth.cols) / w, sy = double(coarse.depth.rows) / h;
#pragma omp parallel for schedule(dynamic, 4)
    for (int y = 0; y < h; ++y) {
      const int cy = std::min(static_cast<int>((y + 0.5) * sy), coarse.depth.rows - 1);
      for (int x = 0; x < w; ++x) {
        const int cx = std::min(static_cast<int>((x + 0.5) * sx), coarse.depth.cols - 1);
        const std::size_t i = std::size_t(y) * w + x;
        const cv::Vec3f cn = coarse.normal.at<cv::Vec3f>(cy, cx);
        const Eigen::Vector3d n(cn[0], cn[1], cn[2]);
        const Eigen::Vector3d on_plane =
            coarse_K_inv * Eigen::Vector3d(cx + 0.5, cy + 0.5, 1.0) * coarse.depth.at<float>(cy, cx);
        const double denom = n.dot(ray(x, y));
        const double depth = std::abs(denom) > 1e-9 ? n.dot(on_plane) / denom : 0.0;
        if (depth > 0.5 / inv_max_ && depth < 2.0 / inv_min_) {
          planes_[i].depth = static_cast<float>(depth);
          planes_[i].normal = n.cast<float>();
          inherited_[i] = coarse.cost.at<float>(cy, cx);
        } else {
          planes_[i] = random_plane(x, y, i * 7919u);
        }
      }
    }
    score_all();
    const float settled_cost = static_cast<float>(options_.refine_settled_cost);
    for (std::size_t i = 0; i < photo_.size(); ++i) settled_[i] = photo_[i] <= settled_cost;
    for_seed_pixels(seeds, [&](int x, int y, const Plane& seed) {
      const std::size_t i = std::size_t(y) * w + x;
      Tried tried;
      if (!settled_[i]) try_plane(x, y, i, seed, tried);
    });
    try_random_planes_where_unsettled();
  }

  // Finer level: a structure the coarse level missed (a bar under one coarse
  // pixel wide) has no plane to propagate from; random planes, as at the
  // coarse level's start, let some of its pixels find it, and the sweeps'
  // propagation carries it along the structure.
  void try_random_planes_where_unsettled() {
    const int w = ref_.width(), h = ref_.height();
#pragma omp parallel for schedule(dynamic, 4)
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t i = std::size_t(y) * w + x;
        if (!textured_[i] || settled_[i]) continue;
        Tried tried;
        for (int k = 1; k <= options_.refine_random_planes; ++k) {
          try_plane(x, y, i, random_plane(x, y, i * 7919u + 104729u * k), tried);
        }
      }
    }
  }

  // One red-black sweep; scale shrinks the random perturbations.
  void iterate(int iteration, double scale, Reporter& reporter) {
    const int w = ref_.width(), h = ref_.height();
    for (int colour = 0; colour < 2; ++colour) {
      reporter.throw_if_cancelled();
#pragma omp parallel for schedule(dynamic, 2)
      for (int y = 0; y < h; ++y) {
        for (int x = (y + colour) % 2; x < w; x += 2) update(x, y, iteration, colour, scale);
      }
    }
  }

  // Per-pixel view selection: each pixel whose plane changed since its
  // views were chosen keeps the options.pixel_source_views sources that
  // score its plane best (photometric + geometric), and later candidates are
  // scored on those alone. They include the best K, so the pixel's own cost
  // stays as it is; a candidate is scored at best as well as on every view
  // (its best K among fewer), so none wins that would not have on all.
  void select_views() {
    const int keep = options_.pixel_source_views;
    const int nsrc = static_cast<int>(std::min<std::size_t>(sources_.size(), 32));
    if (keep == 0 || keep >= nsrc) return;
    const int w = ref_.width(), h = ref_.height();
    const std::uint32_t all = nsrc == 32 ? ~0u : (1u << nsrc) - 1u;
#pragma omp parallel for schedule(dynamic, 4)
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t i = std::size_t(y) * w + x;
        if (!textured_[i] || settled_[i] || !reselect_[i]) continue;
        reselect_[i] = 0;
        views_[i] = all;
        float view_costs[32];
        if (!score_views(x, y, planes_[i], view_costs)) continue;
        std::uint32_t chosen = 0;
        for (int n = 0; n < keep; ++n) {
          int best = -1;
          for (int s = 0; s < nsrc; ++s) {
            if (!(chosen >> s & 1u) && (best < 0 || view_costs[s] < view_costs[best])) best = s;
          }
          chosen |= 1u << best;
        }
        views_[i] = chosen;
      }
    }
  }

  // Planar prior (mvs/planar_prior.h): a pixel not matched confidently
  // scores the plane its confident surroundings span as one more candidate.
  void try_prior_planes(const PriorPlanes& prior, int iteration) {
    const int w = ref_.width(), h = ref_.height();
#pragma omp parallel for schedule(dynamic, 4)
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t i = std::size_t(y) * w + x;
        const cv::Vec3f n = prior.normal.at<cv::Vec3f>(y, x);
        if (!(prior.depth.at<float>(y, x) > 0) || photo_[i] <= options_.planar_prior_confident_cost) continue;
        Tried tried;
        tried.add(planes_[i]);
        if (try_plane(x, y, i, {prior.depth.at<float>(y, x), {n[0], n[1], n[2]}}, tried))
          changed_[i] = static_cast<std::int8_t>(iteration);
      }
    }
  }

  PlaneMap planes() const {
    const int w = ref_.width(), h = ref_.height();
    PlaneMap map;
    map.depth = cv::Mat(h, w, CV_32F);
    map.normal = cv::Mat(h, w, CV_32FC3);
    map.cost = cv::Mat(h, w, CV_32F);
    map.K = ref_.K;
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t i = std::size_t(y) * w + x;
        map.depth.at<float>(y, x) = planes_[i].depth;
        const Eigen::Vector3f& n = planes_[i].normal;
        map.normal.at<cv::Vec3f>(y, x) = cv::Vec3f(n.x(), n.y(), n.z());
        map.cost.at<float>(y, x) = textured_[i] ? photo_[i] : inherited_[i];
      }
    }
    return map;
  }

  void add_refinement_stats(PatchMatchStats& stats) const {
    for (std::size_t i = 0; i < settled_.size(); ++i) {
      stats.refined_pixels += textured_[i] && !settled_[i];
      // The vote was capped: the plane's own photometric cost won.
      stats.restored_pixels += has_priors_ && textured_[i] && photo_[i] < 2.0f &&
                               costs_[i] >= photo_[i] + float(options_.detail_restore_margin) - 1e-6f;
    }
  }

 private:
  // The plane-induced homography from the reference into a source view is
  // K_s (R + t n^T / d) K_ref^-1 = A + b m^T with m = K_ref^-T n / d; A and b
  // depend only on the view pair.
  struct Relative {
    Eigen::Matrix3f A;
    Eigen::Vector3f b;
  };

  // The eight propagation areas: four strips along the axes (distances 1,
  // 3, ..., 2 * kStripLength - 1) and four V-shapes around the diagonals
  // (|dx| + |dy| of 3 and 5). Every offset has odd |dx| + |dy|: the other
  // colour of the red-black sweep, which is not written while this one runs.
  void prepare_propagation_areas() {
    constexpr int kStripLength = 6;
    for (const auto& [ax, ay] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
      auto& strip = propagation_areas_.emplace_back();
      for (int k = 0; k < kStripLength; ++k) strip.emplace_back(ax * (2 * k + 1), ay * (2 * k + 1));
    }
    for (const auto& [sx, sy] : {std::pair{1, 1}, {-1, 1}, {1, -1}, {-1, -1}}) {
      auto& v = propagation_areas_.emplace_back();
      for (const auto& [a, b] : {std::pair{1, 2}, {2, 1}, {1, 4}, {2, 3}, {3, 2}, {4, 1}})
        v.emplace_back(sx * a, sy * b);
    }
  }

  // The pixel of area (offsets from (x, y)) with the lowest cost among those
  // whose plane changed in sweep changed_since or later; (-1, -1) if none.
  Eigen::Vector2i best_in_area(const std::vector<Eigen::Vector2i>& area, int x, int y, int changed_since) const {
    const int w = ref_.width(), h = ref_.height();
    Eigen::Vector2i best(-1, -1);
    float best_cost = 0;
    for (const Eigen::Vector2i& o : area) {
      const int nx = x + o.x(), ny = y + o.y();
      if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
      const std::size_t ni = std::size_t(ny) * w + nx;
      if (changed_[ni] < changed_since) continue;
      if (best.x() < 0 || costs_[ni] < best_cost) {
        best = {nx, ny};
        best_cost = costs_[ni];
      }
    }
    return best;
  }

  // Viewing ray of pixel (x, y) with z = 1.
  Eigen::Vector3d ray(int x, int y) const { return ref_.K_inv * Eigen::Vector3d(x + 0.5, y + 0.5, 1.0); }

  // Calls f(x, y, plane) for the 3x3 pixels around each sparse point's
  // projection: its depth, fronto-parallel.
  template <typename F>
  void for_seed_pixels(const std::vector<Eigen::Vector3d>& seeds, F&& f) const {
    const int w = ref_.width(), h = ref_.height();
    for (const auto& p : seeds) {
      const Eigen::Vector3d xc = ref_.R * p + ref_.t;
      if (xc.z() <= 0) continue;
      const Eigen::Vector3d uv = ref_.K * xc / xc.z();
      const int px = static_cast<int>(uv.x()), py = static_cast<int>(uv.y());
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = px + dx, y = py + dy;
          if (x < 0 || y < 0 || x >= w || y >= h) continue;
          Plane seed;
          seed.depth = static_cast<float>(xc.z());
          seed.normal = -ray(x, y).normalized().cast<float>();
          f(x, y, seed);
        }
      }
    }
  }

  void score_all() {
    const int w = ref_.width(), h = ref_.height();
#pragma omp parallel for schedule(dynamic, 4)
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t i = std::size_t(y) * w + x;
        const Cost c = cost(x, y, planes_[i]);
        costs_[i] = c.effective;
        photo_[i] = c.photo;
      }
    }
  }

  // The coarser depth maps of the sources in the reference camera's frame;
  // geometric errors are measured in the coarse level's pixels.
  void prepare_priors(const std::vector<const DepthPrior*>& priors) {
    priors_.assign(sources_.size(), PriorFrame{});
    for (std::size_t s = 0; s < priors.size() && s < sources_.size(); ++s) {
      const DepthPrior* p = priors[s];
      if (!p || p->depth.empty()) continue;
      PriorFrame& f = priors_[s];
      f.prior = p;
      const Eigen::Matrix3d r = p->R * ref_.R.transpose();
      f.R = r.cast<float>();
      f.t = (p->t - r * ref_.t).cast<float>();
      f.R_back = r.transpose().cast<float>();
      f.t_back = (-(r.transpose() * (p->t - r * ref_.t))).cast<float>();
      f.K = p->K.cast<float>();
      f.K_inv = p->K.inverse().cast<float>();
      geometric_pixel_ = static_cast<float>(p->K(0, 0) / ref_.K(0, 0));
      has_priors_ = true;
    }
  }

  // ACMM's forward-backward reprojection error of the point x_ref (reference
  // camera frame) through source s's coarser depth map, in coarse pixels,
  // as a cost: options.geometric_weight at options.geometric_max_error_px
  // and beyond (also where that map has no depth).
  HOS_INLINED_INTO_CLONES float geometric_cost(int s, const Eigen::Vector3f& x_ref, int x, int y) const {
    const PriorFrame& f = priors_[s];
    if (!f.prior) return 0.0f;
    const float weight = static_cast<float>(options_.geometric_weight);
    const float max_error = static_cast<float>(options_.geometric_max_error_px);
    const Eigen::Vector3f xp = f.R * x_ref + f.t;
    if (!(xp.z() > 0)) return weight;
    const Eigen::Vector3f uv = f.K * xp / xp.z();
    const int qx = static_cast<int>(std::floor(uv.x())), qy = static_cast<int>(std::floor(uv.y()));
    const cv::Mat& depth = f.prior->depth;
    if (qx < 0 || qy < 0 || qx >= depth.cols || qy >= depth.rows) return weight;
    const float d = depth.at<float>(qy, qx);
    if (!(d > 0)) return weight;
    const Eigen::Vector3f back = f.R_back * (f.K_inv * Eigen::Vector3f(qx + 0.5f, qy + 0.5f, 1.0f) * d) + f.t_back;
    if (!(back.z() > 0)) return weight;
    const Eigen::Vector3f ref_uv = ref_.K.cast<float>() * back / back.z();
    const float error = (ref_uv.head<2>() - Eigen::Vector2f(x + 0.5f, y + 0.5f)).norm() * geometric_pixel_;
    return weight * std::min(error, max_error) / max_error;
  }

  Plane random_plane(int x, int y, std::uint64_t seed) const {
    Plane p;
    const double inv = inv_min_ + random_unit(seed) * (inv_max_ - inv_min_);
    p.depth = static_cast<float>(1.0 / inv);
    p.normal = random_normal(x, y, seed + 1);
    return p;
  }

  Eigen::Vector3f random_normal(int x, int y, std::uint64_t seed) const {
    const double z = random_unit(seed) * 2.0 - 1.0, phi = random_unit(seed + 17) * 2.0 * M_PI;
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    Eigen::Vector3d n(s * std::cos(phi), s * std::sin(phi), z);
    return facing_camera(n, x, y);
  }

  // Flips n to face the camera and keeps it away from grazing angles.
  Eigen::Vector3f facing_camera(Eigen::Vector3d n, int x, int y) const {
    const Eigen::Vector3d view = -ray(x, y).normalized();
    if (n.dot(view) < 0) n = -n;
    if (n.dot(view) < 0.1) n = (n + 0.2 * view).normalized();
    return n.normalized().cast<float>();
  }

  // Everything of the bilaterally weighted NCC that depends on the reference
  // window only, once per pixel: weights normalised to sum 1, the weighted
  // and centred reference values w_j (r_j - mean_r) (the covariance with any
  // source window is then a single dot product) and the weighted variance.
  void prepare_windows() {
    const int w = ref_.width(), h = ref_.height();
    const std::size_t k = offsets_.size();
    weights_.assign(std::size_t(w) * h * k, 0.0f);
    centred_.assign(std::size_t(w) * h * k, 0.0f);
    ref_var_.assign(std::size_t(w) * h, 0.0f);
    textured_.assign(std::size_t(w) * h, 0);
    const int r = options_.window_radius;
    const double r2 = double(r) * r;
    std::vector<float> spatial(k);
    for (std::size_t j = 0; j < k; ++j) spatial[j] = static_cast<float>(-offsets_[j].squaredNorm() / (2.0 * r2));
    const float inv_sigma = static_cast<float>(1.0 / options_.sigma_color);
#pragma omp parallel for schedule(static)
    for (int y = r; y < h - r; ++y) {
      std::vector<double> wt(k);
      for (int x = r; x < w - r; ++x) {
        const std::size_t i = std::size_t(y) * w + x;
        // A masked pixel is not matched, and no window counts masked samples.
        if (masked(ref_, x, y)) continue;
        const float centre = ref_.gray.at<float>(y, x);
        double sw = 0, s1 = 0;
        for (std::size_t j = 0; j < k; ++j) {
          const float v = ref_.gray.at<float>(y + offsets_[j].y(), x + offsets_[j].x());
          const bool usable = !masked(ref_, x + offsets_[j].x(), y + offsets_[j].y());
          wt[j] = usable ? std::exp(spatial[j] - std::abs(v - centre) * inv_sigma) : 0.0;
          sw += wt[j];
          s1 += wt[j] * v;
        }
        const double mean = s1 / sw;
        double var = 0;
        for (std::size_t j = 0; j < k; ++j) {
          const double v = ref_.gray.at<float>(y + offsets_[j].y(), x + offsets_[j].x()) - mean;
          weights_[i * k + j] = static_cast<float>(wt[j] / sw);
          centred_[i * k + j] = static_cast<float>(wt[j] / sw * v);
          var += wt[j] / sw * v * v;
        }
        ref_var_[i] = static_cast<float>(var);
        textured_[i] = std::sqrt(var) >= options_.min_texture_std;
      }
    }
  }

  // True where the window's centre (x, y) warped by H lands on a masked
  // pixel of src: src does not see the point usably, as if occluded.
  static bool masked_in_source(int x, int y, const MvsView& src, const Eigen::Matrix3f& H) {
    if (src.mask.empty()) return false;
    const Eigen::Vector3f c = H * Eigen::Vector3f(x + 0.5f, y + 0.5f, 1.0f);
    if (!(c.z() > 1e-6f)) return false;  // the window check rejects it
    const float u = std::floor(c.x() / c.z()), v = std::floor(c.y() / c.z());
    return u >= 0 && v >= 0 && u < float(src.mask.cols) && v < float(src.mask.rows) &&
           masked(src, static_cast<int>(u), static_cast<int>(v));
  }

  // 1 - NCC of the reference window at pixel i = (x, y) against source s
  // through homography H (mvs/window_ncc.h); kWindowUnseen if any part of
  // the warped window leaves the image, lies behind the camera or falls on
  // the source's mask.
  HOS_INLINED_INTO_CLONES float view_cost(int x, int y, std::size_t i, int s, const Eigen::Matrix3f& H) const {
    if (masked_in_source(x, y, *sources_[s], H)) return kWindowUnseen;
    const std::size_t k = offsets_.size();
    NccReference reference;
    reference.x = x + 0.5f;
    reference.y = y + 0.5f;
    reference.centre_value = ref_.gray.at<float>(y, x);
    reference.weights = &weights_[i * k];
    reference.centred = &centred_[i * k];
    reference.variance = ref_var_[i];
    const float h[9] = {H(0, 0), H(0, 1), H(0, 2), H(1, 0), H(1, 1), H(1, 2), H(2, 0), H(2, 1), H(2, 2)};
    return window_ncc_(window_, reference, h, source_quads_[s]);
  }

  // Each source view's cost (1 - NCC plus the geometric vote) of plane at
  // pixel (x, y), into out[s]; false where the plane cannot be scored.
  HOS_CPU_CLONES bool score_views(int x, int y, const Plane& plane, float* out) const {
    const std::size_t i = std::size_t(y) * ref_.width() + x;
    if (!(plane.depth > 0)) return false;
    const Eigen::Vector3d n = plane.normal.cast<double>();
    const Eigen::Vector3d x_ref = ray(x, y) * plane.depth;
    const double nd = n.dot(x_ref);
    if (std::abs(nd) < 1e-12) return false;
    const Eigen::Vector3f m = (ref_.K_inv.transpose() * n / nd).cast<float>();
    const int nsrc = static_cast<int>(std::min<std::size_t>(sources_.size(), 32));
    for (int s = 0; s < nsrc; ++s) {
      const Eigen::Matrix3f H = relative_[s].A + relative_[s].b * m.transpose();
      // A source that does not see the window ranks last.
      out[s] = std::min(view_cost(x, y, i, s, H), 2.0f) +
               (has_priors_ ? geometric_cost(s, x_ref.cast<float>(), x, y) : 0.0f);
    }
    return true;
  }

  // Cost of plane at pixel (x, y): the mean of the best K source views,
  // each scored by its 1 - NCC plus (finer levels) its geometric vote. A
  // source that does not see the window counts as options.unseen_view_cost,
  // so a surface near the edge of the sources' frames, which fewer than K
  // of them see, can still match; a plane no source sees cannot.
  // Stops early, returning a lower bound >= to_beat, once the views still to
  // be scored (each at best 0) cannot bring the cost below it.
  HOS_CPU_CLONES Cost cost(int x, int y, const Plane& plane, float to_beat = 3.0f) const {
    const std::size_t i = std::size_t(y) * ref_.width() + x;
    if (!textured_[i] || !(plane.depth > 0)) return {};
    const Eigen::Vector3d n = plane.normal.cast<double>();
    const Eigen::Vector3d x_ref = ray(x, y) * plane.depth;
    const double nd = n.dot(x_ref);
    if (std::abs(nd) < 1e-12) return {};
    const Eigen::Vector3f m = (ref_.K_inv.transpose() * n / nd).cast<float>();
    // The pixel's source views (bit s: source s; all until select_views).
    std::uint32_t views = views_[i];
    const int nsrc = std::popcount(views);
    if (nsrc == 0) return {};
    const int best = std::min(options_.best_k, nsrc);
    const float margin = static_cast<float>(options_.detail_restore_margin);
    // The view costs so far (photometric + geometric, and photometric
    // alone) in ascending order of the former, and the photometric ones
    // ascending on their own for the early-exit bound.
    float sorted[32], sorted_photo[32], photo_only[32];
    int seen = 0;
    for (int s = 0; s < nsrc; ++s) {
      const int v = std::countr_zero(views);
      views &= views - 1;
      const Eigen::Matrix3f H = relative_[v].A + relative_[v].b * m.transpose();
      float photo = view_cost(x, y, i, v, H);
      if (photo == kWindowUnseen) {
        photo = unseen_view_cost_;
      } else {
        ++seen;
      }
      const float c = photo + (has_priors_ ? geometric_cost(v, x_ref.cast<float>(), x, y) : 0.0f);
      int j = s;
      for (; j > 0 && sorted[j - 1] > c; --j) {
        sorted[j] = sorted[j - 1];
        sorted_photo[j] = sorted_photo[j - 1];
      }
      sorted[j] = c;
      sorted_photo[j] = photo;
      j = s;
      for (; j > 0 && photo_only[j - 1] > photo; --j) photo_only[j] = photo_only[j - 1];
      photo_only[j] = photo;
      const int known = best - (nsrc - 1 - s);  // best-K members that must be among the scored views
      if (known > 0 && s + 1 < nsrc) {
        float bound = 0, photo_bound = 0;
        for (int b = 0; b < known; ++b) {
          bound += sorted[b];
          photo_bound += photo_only[b];
        }
        const float lower = std::min(bound, photo_bound + margin * best) / best;
        if (lower >= to_beat) return {lower, lower};
      }
    }
    if (seen == 0) return {};
    float sum = 0, photo_sum = 0;
    for (int s = 0; s < best; ++s) {
      sum += sorted[s];
      photo_sum += sorted_photo[s];
    }
    const float photo = photo_sum / best;
    return {has_priors_ ? std::min(sum / best, photo + margin) : photo, photo};
  }

  // Planes already scored at one pixel during one update. Neighbours on the
  // same surface propagate (nearly) the plane the pixel already has; scoring
  // it again cannot change the result, and skipping it saves most of the
  // propagation cost once the sweeps have converged.
  struct Tried {
    Plane planes[16];
    int count = 0;
    bool contains(const Plane& p) const {
      for (int j = 0; j < count; ++j) {
        if (std::abs(planes[j].depth - p.depth) <= 1e-5f * p.depth && planes[j].normal.dot(p.normal) >= 0.99999f) {
          return true;
        }
      }
      return false;
    }
    void add(const Plane& p) {
      if (count < 16) planes[count++] = p;
    }
  };

  // Scores candidate at pixel i and keeps it if it is better; true if kept.
  bool try_plane(int x, int y, std::size_t i, const Plane& candidate, Tried& tried) {
    if (!(candidate.depth > 0) || !std::isfinite(candidate.depth) || tried.contains(candidate)) return false;
    tried.add(candidate);
    const Cost c = cost(x, y, candidate, costs_[i]);
    if (!(c.effective < costs_[i])) return false;
    costs_[i] = c.effective;
    photo_[i] = c.photo;
    planes_[i] = candidate;
    reselect_[i] = 1;
    return true;
  }

  void update(int x, int y, int iteration, int colour, double scale) {
    const int w = ref_.width();
    const std::size_t i = std::size_t(y) * w + x;
    if (!textured_[i] || settled_[i]) return;
    Tried tried;
    tried.add(planes_[i]);
    bool changed = false;
    // A neighbour whose plane has not changed since this pixel's previous
    // update already competed then (its area's best was scored, and this
    // pixel's cost has only fallen since), so it is passed over. Colour 0
    // last ran before the previous sweep's colour-1 pass, colour 1 before
    // this sweep's colour-0 pass.
    const int unchanged_before = colour == 0 ? iteration - 1 : iteration;
    // Adaptive checkerboard propagation (after ACMH, Xu and Tao 2019): from
    // each of eight areas of the other colour, the plane that scores best at
    // its own pixel. Long strips carry a plane along a thin structure in few
    // sweeps.
    for (const auto& area : propagation_areas_) {
      const Eigen::Vector2i best = best_in_area(area, x, y, iteration > 0 ? unchanged_before : -1);
      if (best.x() < 0) continue;
      const Plane& neighbour = planes_[std::size_t(best.y()) * w + best.x()];
      // The neighbour's plane, re-intersected with this pixel's ray.
      Plane candidate = neighbour;
      const Eigen::Vector3d n = neighbour.normal.cast<double>();
      const Eigen::Vector3d xn = ray(best.x(), best.y()) * neighbour.depth;
      const double denom = n.dot(ray(x, y));
      if (std::abs(denom) < 1e-9) continue;
      candidate.depth = static_cast<float>(n.dot(xn) / denom);
      if (candidate.depth < 0.5 / inv_max_ || candidate.depth > 2.0 / inv_min_) continue;
      changed |= try_plane(x, y, i, candidate, tried);
    }
    // Random refinement: perturb depth and normal, shrinking per iteration.
    const std::uint64_t seed = (std::uint64_t(i) * 131 + iteration) * 1000003ull;
    const Plane current = planes_[i];
    Plane perturbed = current;
    const double range = (1.0 / inv_min_ - 1.0 / inv_max_) * 0.05 * scale;
    perturbed.depth = static_cast<float>(current.depth + (random_unit(seed) * 2 - 1) * range);
    const Eigen::Vector3d dn(random_unit(seed + 1) - 0.5, random_unit(seed + 2) - 0.5, random_unit(seed + 3) - 0.5);
    perturbed.normal = facing_camera(current.normal.cast<double>() + 0.6 * scale * dn, x, y);
    changed |= try_plane(x, y, i, perturbed, tried);
    Plane depth_only = current;
    depth_only.depth = perturbed.depth;
    changed |= try_plane(x, y, i, depth_only, tried);
    Plane normal_only = current;
    normal_only.normal = perturbed.normal;
    changed |= try_plane(x, y, i, normal_only, tried);
    changed |= try_plane(x, y, i, random_plane(x, y, seed + 5), tried);
    if (changed) changed_[i] = static_cast<std::int8_t>(iteration);
  }

  const MvsView& ref_;
  const std::vector<const MvsView*>& sources_;
  const MvsOptions& options_;
  double inv_min_, inv_max_;
  std::vector<Eigen::Vector2i> offsets_;
  std::vector<float> offset_x_, offset_y_;  // offsets_, padded to kNccLanes
  NccWindow window_;
  WindowNccFunction window_ncc_ = best_window_ncc();
  float unseen_view_cost_ = static_cast<float>(options_.unseen_view_cost);
  std::vector<QuadImage> source_quads_;  // per source view
  std::vector<Relative> relative_;
  std::vector<std::vector<Eigen::Vector2i>> propagation_areas_;
  std::vector<Plane> planes_;
  std::vector<float> costs_;          // Cost::effective
  std::vector<float> photo_;          // Cost::photo
  std::vector<std::int8_t> changed_;  // sweep in which the pixel's plane last changed, -1: never
  std::vector<float> weights_, centred_, ref_var_;
  std::vector<char> textured_;
  std::vector<char> settled_;  // finer levels: the upsampled plane matched well, no sweeps
  // Per pixel, the source views its planes are scored on (bit s: source s)
  // and whether its plane changed since they were chosen.
  std::vector<std::uint32_t> views_;
  std::vector<char> reselect_;
  // Finer levels: the coarser pixel's cost. A window flat at this level
  // whose coarser pixel matched (its window spans twice the scene and saw
  // texture) keeps the upsampled plane and that cost; kTexturelessCost elsewhere.
  std::vector<float> inherited_;
  std::vector<PriorFrame> priors_;
  bool has_priors_ = false;
  float geometric_pixel_ = 1.0f;  // coarse pixels per reference pixel
};

}  // namespace

namespace {

// Masks shrink with their images, pixel for pixel (nearest, no blending).
cv::Mat resized_mask(const cv::Mat& mask, cv::Size size) {
  if (mask.empty() || mask.size() == size) return mask;
  cv::Mat out;
  cv::resize(mask, out, size, 0, 0, cv::INTER_NEAREST);
  return out;
}

}  // namespace

MvsView load_view(const UndistortedWorkspace& workspace, const ImageRecord& image, int max_image_size) {
  const auto path = workspace.image_path(image);
  cv::Mat color = cv::imread(path.string(), cv::IMREAD_COLOR);
  if (color.empty()) throw InputError(path.string(), "cannot read the image");
  const Camera& camera = workspace.model.camera_of(image);
  if (color.cols != camera.width || color.rows != camera.height) {
    throw InputError(path.string(), "image is " + std::to_string(color.cols) + "x" + std::to_string(color.rows) +
                                        " but its camera says " + std::to_string(camera.width) + "x" +
                                        std::to_string(camera.height));
  }
  const double scale = std::min(1.0, double(max_image_size) / std::max(color.cols, color.rows));
  MvsView view;
  view.image_id = image.id;
  view.name = image.name;
  if (scale < 1.0) {
    cv::resize(color, view.color, cv::Size(), scale, scale, cv::INTER_AREA);
  } else {
    view.color = color;
  }
  // Exact scale per axis after rounding, so pixel edges keep matching.
  const double sx = double(view.color.cols) / color.cols, sy = double(view.color.rows) / color.rows;
  cv::Mat gray;
  cv::cvtColor(view.color, gray, cv::COLOR_BGR2GRAY);
  gray.convertTo(view.gray, CV_32F, 1.0 / 255.0);
  Eigen::Matrix3d K = camera.calibration_matrix();
  K.row(0) *= sx;
  K.row(1) *= sy;
  view.K = K;
  view.K_inv = K.inverse();
  view.mask = resized_mask(load_workspace_mask(workspace, image), view.color.size());
  view.R = image.rotation();
  view.t = image.cam_from_world_translation;
  return view;
}

MvsView downscale_view(const MvsView& view, int max_image_size) {
  const double scale = std::min(1.0, double(max_image_size) / std::max(view.width(), view.height()));
  if (scale >= 1.0) return view;
  MvsView small = view;
  cv::resize(view.color, small.color, cv::Size(), scale, scale, cv::INTER_AREA);
  cv::resize(view.gray, small.gray, small.color.size(), 0, 0, cv::INTER_AREA);
  small.mask = resized_mask(view.mask, small.color.size());
  // Exact scale per axis after rounding, so pixel edges keep matching.
  small.K.row(0) *= double(small.color.cols) / view.color.cols;
  small.K.row(1) *= double(small.color.rows) / view.color.rows;
  small.K_inv = small.K.inverse();
  return small;
}

double matcher_bytes_per_pixel(const MvsOptions& options) {
  const int side = 2 * options.window_radius / options.window_step + 1;
  // Two floats per window sample (weights, centred values), the Plane, four
  // floats (costs, photometric costs, inherited costs, variance), the view
  // mask, four bytes (changed, settled, textured, reselect) and each
  // source's 8-bit copy for the window kernel (mvs/window_ncc.h).
  return 2.0 * sizeof(float) * side * side + sizeof(Plane) + 4.0 * sizeof(float) + sizeof(std::uint32_t) + 4.0 +
         sizeof(std::uint16_t) * options.num_source_views;
}

PlaneMap match_planes(const MvsView& ref,
                      const std::vector<const MvsView*>& sources,
                      double depth_min,
                      double depth_max,
                      const std::vector<Eigen::Vector3d>& seed_points,
                      const MvsOptions& options,
                      Reporter& reporter) {
  PatchMatcher matcher(ref, sources, depth_min, depth_max, options);
  matcher.initialise(seed_points);
  for (int it = 0; it < options.iterations; ++it) {
    // The first sweep's random planes say nothing about which views see the pixel.
    if (it > 0) matcher.select_views();
    if (options.planar_prior && it > 0 && it + 1 == options.iterations) {
      matcher.try_prior_planes(planar_prior(matcher.planes(), options.planar_prior_confident_cost), it);
    }
    matcher.iterate(it, 1.0 / (1 << it), reporter);
  }
  return matcher.planes();
}

PlaneMap refine_planes(const MvsView& ref,
                       const std::vector<const MvsView*>& sources,
                       const std::vector<const DepthPrior*>& priors,
                       const PlaneMap& coarse,
                       double depth_min,
                       double depth_max,
                       const std::vector<Eigen::Vector3d>& seed_points,
                       const MvsOptions& options,
                       Reporter& reporter,
                       PatchMatchStats* stats) {
  PatchMatcher matcher(ref, sources, depth_min, depth_max, options, priors);
  matcher.initialise_from(coarse, seed_points);
  // Perturbations continue from where the coarse level's sweeps stopped.
  for (int it = 0; it < options.refine_iterations; ++it) {
    matcher.select_views();
    matcher.iterate(it, 1.0 / (1 << (options.iterations + it)), reporter);
  }
  if (stats) matcher.add_refinement_stats(*stats);
  return matcher.planes();
}

DepthMap to_depth_map(const PlaneMap& planes, const MvsView& ref, const MvsOptions& options, PatchMatchStats* stats) {
  const int w = planes.depth.cols, h = planes.depth.rows;
  DepthMap map;
  map.depth = cv::Mat::zeros(h, w, CV_32F);
  map.normal = cv::Mat::zeros(h, w, CV_32FC3);
  map.cost = planes.cost.clone();
  const Eigen::Matrix3f r_world = ref.R.transpose().cast<float>();
  PatchMatchStats s;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (masked(ref, x, y)) continue;  // no depth from a masked pixel
      const float c = planes.cost.at<float>(y, x);
      if (c == kTexturelessCost) {
        ++s.textureless_pixels;
        continue;
      }
      if (!(c <= options.max_cost)) continue;
      map.depth.at<float>(y, x) = planes.depth.at<float>(y, x);
      const cv::Vec3f nc = planes.normal.at<cv::Vec3f>(y, x);
      const Eigen::Vector3f n = r_world * Eigen::Vector3f(nc[0], nc[1], nc[2]);
      map.normal.at<cv::Vec3f>(y, x) = cv::Vec3f(n.x(), n.y(), n.z());
      ++s.valid_pixels;
    }
  }
  if (stats) {
    stats->valid_pixels = s.valid_pixels;
    stats->textureless_pixels = s.textureless_pixels;
  }
  return map;
}

DepthMap estimate_depth_map(const MvsView& ref,
                            const std::vector<const MvsView*>& sources,
                            double depth_min,
                            double depth_max,
                            const std::vector<Eigen::Vector3d>& seed_points,
                            const MvsOptions& options,
                            Reporter& reporter,
                            PatchMatchStats* stats) {
  return to_depth_map(match_planes(ref, sources, depth_min, depth_max, seed_points, options, reporter), ref, options,
                      stats);
}

}  // namespace hos::mvs
