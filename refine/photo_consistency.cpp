#include "refine/photo_consistency.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace hos::refine {
namespace {

constexpr float kMinPatchStd = 0.01f;  // grey levels in [0, 1]; flatter patches give no score
constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

// The reference view (most frontal) and the views compared with it, for one vertex.
struct ViewChoice {
  int reference = -1;
  std::vector<int> compared;
};

ViewChoice choose_views(const Eigen::Vector3d& x,
                        const Eigen::Vector3d& n,
                        const std::vector<RefineView>& views,
                        double visibility_tolerance,
                        const RefineOptions& o) {
  // Step 1: the views that see the vertex not too grazingly, by how frontally.
  std::vector<std::pair<double, int>> candidates;
  const double min_cos_incidence = std::cos(o.max_incidence_deg * kDegToRad);
  for (std::size_t i = 0; i < views.size(); ++i) {
    const double c = n.dot((views[i].center - x).normalized());
    if (c > min_cos_incidence && sees(views[i], x, visibility_tolerance))
      candidates.emplace_back(c, static_cast<int>(i));
  }
  std::sort(candidates.begin(), candidates.end(), std::greater<>());
  ViewChoice choice;
  if (candidates.empty()) return choice;
  // Step 2: the most frontal is the reference; the others within the
  // baseline range are compared with it (too narrow: depth is ill-conditioned).
  choice.reference = candidates[0].second;
  const Eigen::Vector3d ray_ref = (views[choice.reference].center - x).normalized();
  const double cos_min = std::cos(o.min_angle_deg * kDegToRad), cos_max = std::cos(o.max_angle_deg * kDegToRad);
  for (std::size_t k = 1; k < candidates.size() && static_cast<int>(choice.compared.size()) < o.max_views; ++k) {
    const double c = ray_ref.dot((views[candidates[k].second].center - x).normalized());
    if (c <= cos_min && c >= cos_max) choice.compared.push_back(candidates[k].second);
  }
  return choice;
}

// The patch: the current surface as the reference view sees it around the
// vertex (one point per pixel of the level, from the depth buffer), with the
// reference's grey levels. Following the surface instead of a tangent plane
// keeps curvature from biasing the offset. Samples off that surface (past a
// silhouette, across a depth edge) are left out; with fewer than
// min_coverage of them left there is no patch.
//
// An offset moves the surface along the vertex normal, but each sample stays
// on its reference pixel's ray (its grey level belongs to that ray):
// `along_ray` is the move along the ray that shifts the surface by one unit
// along the normal. Moving the samples along the normal instead would slide
// them across the reference's texture whenever the reference sees the
// surface obliquely, and bias the offset found.
struct Patch {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> along_ray;
  std::vector<float> reference;
};

std::optional<Patch> surface_patch(const RefineView& ref,
                                   int level,
                                   const Eigen::Vector3d& x,
                                   const Eigen::Vector3d& n,
                                   double min_cos_incidence,
                                   int half,
                                   double step,
                                   double max_depth_jump,
                                   double min_coverage) {
  const std::optional<Eigen::Vector3d> centre = ref.project(x, level);
  if (!centre) return std::nullopt;
  Patch patch;
  for (int b = -half; b <= half; ++b) {
    for (int a = -half; a <= half; ++a) {
      // Pixel centres of the level nearest to the vertex's projection.
      const Eigen::Vector2d pixel(std::floor(centre->x()) + 0.5 + a * step, std::floor(centre->y()) + 0.5 + b * step);
      const std::optional<Eigen::Vector3d> point = surface_point(ref, pixel, max_depth_jump);
      const std::optional<float> grey = sample(ref, level, pixel);
      if (!point || !grey) continue;
      const Eigen::Vector3d ray = (*point - ref.center).normalized();
      // n faces the reference, so n . ray < 0; bounded away from 0 at grazing pixels.
      const double cos_incidence = std::min(n.dot(ray), -min_cos_incidence);
      patch.points.push_back(*point);
      patch.along_ray.push_back(ray / cos_incidence);
      patch.reference.push_back(*grey);
    }
  }
  const double side = 2.0 * half + 1.0;
  if (static_cast<double>(patch.points.size()) < min_coverage * side * side) return std::nullopt;
  return patch;
}

// The reference's grey levels centred on their mean: ZNCC against every
// offset and view then needs only the other patch's sums.
struct CentredPatch {
  std::vector<float> centred;
  float variance = 0.0f;  // sum of squares of centred
};

CentredPatch centre(const std::vector<float>& a) {
  const float n = static_cast<float>(a.size());
  float mean = 0;
  for (float v : a) mean += v;
  mean /= n;
  CentredPatch c;
  c.centred.resize(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    c.centred[i] = a[i] - mean;
    c.variance += c.centred[i] * c.centred[i];
  }
  return c;
}

std::optional<float> zncc_centred(const CentredPatch& a, const float* b, float min_std) {
  // a is centred, so the covariance is sum a_i b_i and b's sums give its
  // variance: one pass over b.
  const std::size_t size = a.centred.size();
  const float n = static_cast<float>(size);
  float sum_b = 0, sum_bb = 0, cov = 0;
  for (std::size_t i = 0; i < size; ++i) {
    sum_b += b[i], sum_bb += b[i] * b[i], cov += a.centred[i] * b[i];
  }
  const float var_b = std::max(0.0f, sum_bb - sum_b * sum_b / n);
  const float min_var = min_std * min_std * n;
  if (a.variance < min_var || var_b < min_var) return std::nullopt;
  return cov / std::sqrt(a.variance * var_b);
}

// The grey levels of the patch moved by k * step along the normal
// (k = -steps .. steps) in another view: out[(k + steps) * n + i] for the
// patch's n points; valid[k + steps] is false when a point leaves the image
// at that offset (or lands on a masked pixel). Each point and its ray move are taken into the view's
// camera frame once, so an offset costs a division and a lookup per point.
void sample_moved_patch(const RefineView& view,
                        int level,
                        const Patch& patch,
                        double step,
                        int steps,
                        std::vector<float>& out,
                        std::vector<char>& valid) {
  const std::size_t n = patch.points.size();
  const int offsets = 2 * steps + 1;
  out.assign(n * offsets, 0.0f);
  valid.assign(offsets, 1);
  const double scale = 1.0 / static_cast<double>(1 << level);
  const float fx = static_cast<float>(view.camera.focal_x() * scale),
              fy = static_cast<float>(view.camera.focal_y() * scale);
  const float cx = static_cast<float>(view.camera.principal_x() * scale) - 0.5f;
  const float cy = static_cast<float>(view.camera.principal_y() * scale) - 0.5f;
  const cv::Mat& image = view.pyramid[level];
  const float max_x = static_cast<float>(image.cols - 1), max_y = static_cast<float>(image.rows - 1);
  const auto* data = image.ptr<std::uint16_t>(0);
  const std::size_t stride = image.step1();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f x0 = (view.rotation * patch.points[i] + view.pose.cam_from_world_translation).cast<float>();
    const Eigen::Vector3f move = (view.rotation * (step * patch.along_ray[i])).cast<float>();
    for (int k = 0; k < offsets; ++k) {
      if (!valid[k]) continue;
      const Eigen::Vector3f x = x0 + static_cast<float>(k - steps) * move;
      // Pixel coordinates from the top-left pixel's centre.
      const float inverse_z = 1.0f / x.z();
      const float u = fx * x.x() * inverse_z + cx, v = fy * x.y() * inverse_z + cy;
      if (!(x.z() > 0.0f && u >= 0.0f && v >= 0.0f && u <= max_x && v <= max_y)) {
        valid[k] = 0;
        continue;
      }
      const int x_0 = std::min(static_cast<int>(u), image.cols - 2),
                y_0 = std::min(static_cast<int>(v), image.rows - 2);
      if (!usable_sample(view, level, x_0, y_0)) {
        valid[k] = 0;
        continue;
      }
      const float wx = u - static_cast<float>(x_0), wy = v - static_cast<float>(y_0);
      const std::uint16_t* p = data + static_cast<std::size_t>(y_0) * stride + x_0;
      const float top = p[0] + wx * (static_cast<float>(p[1]) - p[0]);
      const float bottom = p[stride] + wx * (static_cast<float>(p[stride + 1]) - p[stride]);
      out[k * n + i] = (top + wy * (bottom - top)) * (1.0f / 65535.0f);
    }
  }
}

// Mean of the better half of the scores (at least one): an occluder in one
// view does not veto a surface the others agree on.
float robust_mean(std::vector<float>& scores) {
  std::sort(scores.begin(), scores.end(), std::greater<>());
  const std::size_t keep = std::max<std::size_t>(1, (scores.size() + 1) / 2);
  return std::accumulate(scores.begin(), scores.begin() + keep, 0.0f) / static_cast<float>(keep);
}

VertexTarget search_vertex(const Eigen::Vector3d& x,
                           const Eigen::Vector3d& n,
                           const std::vector<RefineView>& views,
                           int level,
                           double visibility_tolerance,
                           const RefineOptions& o) {
  VertexTarget target;
  const ViewChoice choice = choose_views(x, n, views, visibility_tolerance, o);
  if (choice.compared.empty()) return target;
  // Step 1: sizes in scene units from the reference view's pixel footprint.
  const RefineView& ref = views[choice.reference];
  const double depth = ref.pose.cam_from_world(x).z();
  const double footprint = depth / ref.camera.focal_x() * static_cast<double>(1 << level);
  const double step = o.step_pixels * footprint;
  const int steps = o.search_steps;
  const std::optional<Patch> patch =
      surface_patch(ref, level, x, n, std::cos(o.max_incidence_deg * kDegToRad), o.patch_size / 2, o.sample_pixels,
                    visibility_tolerance, o.min_patch_coverage);
  if (!patch) return target;
  // Step 2: the score of each offset of the patch along the normal.
  const CentredPatch reference = centre(patch->reference);
  const std::size_t samples_per_offset = patch->points.size();
  std::vector<std::vector<float>> view_scores(2 * steps + 1);
  std::vector<float> samples;
  std::vector<char> valid;
  for (int j : choice.compared) {
    sample_moved_patch(views[j], level, *patch, step, steps, samples, valid);
    for (int k = 0; k <= 2 * steps; ++k) {
      if (!valid[k]) continue;
      if (const std::optional<float> s = zncc_centred(reference, &samples[k * samples_per_offset], kMinPatchStd)) {
        view_scores[k].push_back(*s);
      }
    }
  }
  std::vector<float> scores(2 * steps + 1, -2.0f);
  for (int k = 0; k <= 2 * steps; ++k) {
    if (!view_scores[k].empty()) scores[k] = robust_mean(view_scores[k]);
  }
  // Step 3: the best offset, refined by a parabola through its neighbours.
  const int best = static_cast<int>(std::max_element(scores.begin(), scores.end()) - scores.begin());
  const float best_score = scores[best];
  if (best_score < o.min_zncc) return target;
  double offset = (best - steps) * step;
  const bool at_end = best == 0 || best == 2 * steps;
  if (!at_end && scores[best - 1] > -2.0f && scores[best + 1] > -2.0f) {
    const double denom = scores[best - 1] - 2.0 * best_score + scores[best + 1];
    if (denom < 0.0) offset += 0.5 * (scores[best - 1] - scores[best + 1]) / denom * step;
  }
  // Step 4: trust grows with the score; a peak at the end of the range may
  // lie beyond it, so it counts half (the next round searches from there).
  target.offset = static_cast<float>(offset);
  target.score = best_score;
  target.weight = static_cast<float>((best_score - o.min_zncc) / (1.0 - o.min_zncc)) * (at_end ? 0.5f : 1.0f);
  return target;
}

}  // namespace

std::optional<float> zncc(const std::vector<float>& a, const std::vector<float>& b, float min_std) {
  return zncc_centred(centre(a), b.data(), min_std);
}

std::vector<VertexTarget> search_normal_offsets(const TriangleMesh& mesh,
                                                const std::vector<Eigen::Vector3f>& normals,
                                                const std::vector<RefineView>& views,
                                                int level,
                                                double visibility_tolerance,
                                                const RefineOptions& options,
                                                Reporter& reporter) {
  std::vector<int> all(mesh.vertices.size());
  std::iota(all.begin(), all.end(), 0);
  return search_normal_offsets(mesh, normals, all, views, level, visibility_tolerance, options, reporter);
}

std::vector<VertexTarget> search_normal_offsets(const TriangleMesh& mesh,
                                                const std::vector<Eigen::Vector3f>& normals,
                                                const std::vector<int>& vertices,
                                                const std::vector<RefineView>& views,
                                                int level,
                                                double visibility_tolerance,
                                                const RefineOptions& options,
                                                Reporter& reporter) {
  std::vector<VertexTarget> targets(mesh.vertices.size());
  const int n = static_cast<int>(vertices.size());
  // Large chunks: every chunk ends in a barrier, where a thread that finished
  // early spins; cancellation is checked between chunks.
  constexpr int kChunk = 32768;
  for (int begin = 0; begin < n; begin += kChunk) {
    reporter.throw_if_cancelled();
    const int end = std::min(n, begin + kChunk);
#pragma omp parallel for schedule(dynamic, 64)
    for (int i = begin; i < end; ++i) {
      const int v = vertices[i];
      if (normals[v].squaredNorm() == 0.0f) continue;
      targets[v] = search_vertex(mesh.vertices[v].cast<double>(), normals[v].cast<double>(), views, level,
                                 visibility_tolerance, options);
    }
  }
  return targets;
}

}  // namespace hos::refine
