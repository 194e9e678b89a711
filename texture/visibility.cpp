#include "texture/visibility.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/image_mask.h"
#include "render/depth_buffer.h"

namespace hos::texture {

namespace {

// Projected vertices of one view: continuous pixel x, y and camera depth z.
std::vector<Eigen::Vector3f> project_vertices(const TriangleMesh& mesh, const TextureView& view) {
  std::vector<Eigen::Vector3f> p(mesh.vertices.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    p[i] = view.project(mesh.vertices[i].cast<double>()).cast<float>();
  }
  return p;
}

// A masked pixel of the view (texture/texture_view.h) under p; outside the
// image is the depth test's business.
bool on_masked_pixel(const TextureView& view, const Eigen::Vector3f& p) {
  if (view.mask.empty()) return false;
  const int x = std::clamp(static_cast<int>(std::floor(p.x())), 0, view.mask.cols - 1);
  const int y = std::clamp(static_cast<int>(std::floor(p.y())), 0, view.mask.rows - 1);
  return view.mask.at<unsigned char>(y, x) == kMaskedOut;
}

bool passes_depth_test(const render::DepthBuffer& buffer, const Eigen::Vector3f& p, int face, float tolerance) {
  const int x = static_cast<int>(std::floor(p.x()));
  const int y = static_cast<int>(std::floor(p.y()));
  if (x < 0 || y < 0 || x >= buffer.depth.cols || y >= buffer.depth.rows) return false;
  if (buffer.face_id.at<int>(y, x) == face) return true;
  const float d = buffer.depth.at<float>(y, x);
  return p.z() <= d * (1.0f + tolerance);
}

// |grad I| of the photo's grey levels (Sobel, per pixel).
cv::Mat gradient_magnitude(const cv::Mat& image) {
  cv::Mat grey, gx, gy, gradient;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  cv::Sobel(grey, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
  cv::Sobel(grey, gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
  cv::magnitude(gx, gy, gradient);
  return gradient;
}

// Per-face sums over the pixels of this view where the face is in front.
struct PixelSums {
  float gradient = 0.0f;
  float count = 0.0f;
  Eigen::Vector3f rgb = Eigen::Vector3f::Zero();
  bool masked = false;  // some pixel of the face is masked out
};

std::vector<PixelSums> sums_over_visible_pixels(const render::DepthBuffer& buffer,
                                                const cv::Mat& gradient,
                                                const TextureView& view,
                                                int num_faces) {
  std::vector<PixelSums> acc(num_faces);
  for (int y = 0; y < buffer.face_id.rows; ++y) {
    const int* ids = buffer.face_id.ptr<int>(y);
    const float* g = gradient.ptr<float>(y);
    const cv::Vec3b* px = view.image.ptr<cv::Vec3b>(y);
    const unsigned char* mask = view.mask.empty() ? nullptr : view.mask.ptr<unsigned char>(y);
    for (int x = 0; x < buffer.face_id.cols; ++x) {
      if (ids[x] < 0) continue;
      PixelSums& a = acc[ids[x]];
      if (mask != nullptr && mask[x] == kMaskedOut) {
        a.masked = true;
        continue;
      }
      a.gradient += g[x];
      a.count += 1.0f;
      a.rgb += Eigen::Vector3f(px[x][2], px[x][1], px[x][0]);
    }
  }
  return acc;
}

}  // namespace

ViewSamples compute_view_visibility(const TriangleMesh& mesh,
                                    const MeshTopology& topology,
                                    const TextureView& view,
                                    int view_index,
                                    const TextureOptions& options) {
  const int num_faces = static_cast<int>(mesh.faces.size());
  const float cos_max = static_cast<float>(std::cos(options.max_view_angle_deg * M_PI / 180.0));
  const float tolerance = static_cast<float>(options.depth_tolerance);
  const std::vector<Eigen::Vector3f> projected = project_vertices(mesh, view);
  const render::DepthBuffer buffer = render::rasterize_depth(mesh, projected, view.camera.width, view.camera.height);

  const cv::Mat gradient = gradient_magnitude(view.image);
  const std::vector<PixelSums> acc = sums_over_visible_pixels(buffer, gradient, view, num_faces);

  const Eigen::Vector3f center = view.pose.center().cast<float>();
  ViewSamples out;
  for (int f = 0; f < num_faces; ++f) {
    const auto& face = mesh.faces[f];
    if (topology.face_areas[f] <= 0.0f) continue;
    const Eigen::Vector3f centroid = (mesh.vertices[face[0]] + mesh.vertices[face[1]] + mesh.vertices[face[2]]) / 3.0f;
    const Eigen::Vector3f to_camera = (center - centroid).normalized();
    const float cos_angle = topology.face_normals[f].dot(to_camera);
    if (cos_angle < cos_max) continue;
    const Eigen::Vector3f& a = projected[face[0]];
    const Eigen::Vector3f& b = projected[face[1]];
    const Eigen::Vector3f& c = projected[face[2]];
    bool inside = true;
    for (const Eigen::Vector3f* p : {&a, &b, &c}) {
      inside = inside && p->z() > render::kMinDepth && p->x() >= 0.0f && p->y() >= 0.0f &&
               p->x() <= view.camera.width && p->y() <= view.camera.height;
    }
    if (!inside) continue;
    const Eigen::Vector3f pc = (a + b + c) / 3.0f;
    // Centroid and points halfway to the corners: a face half hidden by an
    // occluder fails, so occluders are never sampled into the texture.
    bool visible = passes_depth_test(buffer, pc, f, tolerance);
    for (const Eigen::Vector3f* p : {&a, &b, &c}) {
      visible = visible && passes_depth_test(buffer, 0.5f * (pc + *p), f, tolerance);
    }
    // Masked pixels are treated as occluded: a face touching one (or too
    // small to cover a pixel, lying on one) takes no colour from this view.
    bool masked = acc[f].masked;
    for (const Eigen::Vector3f* p : {&a, &b, &c, &pc}) masked = masked || on_masked_pixel(view, *p);
    if (!visible || masked) continue;
    FaceViewSample s;
    s.view = view_index;
    s.cos_angle = cos_angle;
    s.projected_area_px = 0.5f * std::abs((b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x()));
    const PixelSums& sum = acc[f];
    if (sum.count > 0.0f) {
      s.visible_px = sum.count;
      s.gradient_integral = sum.gradient;
      s.mean_rgb = sum.rgb / sum.count;
    } else {
      // Sub-pixel face: one sample at the centroid stands for its area.
      s.visible_px = s.projected_area_px;
      s.gradient_integral = sample_float(gradient, pc.x(), pc.y()) * s.projected_area_px;
      s.mean_rgb = sample_rgb(view.image, pc.x(), pc.y());
    }
    out.emplace_back(f, s);
  }
  return out;
}

FaceViewCandidates gather_candidates(int num_faces, std::vector<ViewSamples>& per_view) {
  FaceViewCandidates result;
  result.offsets.assign(num_faces + 1, 0);
  for (const auto& list : per_view) {
    for (const auto& [f, s] : list) ++result.offsets[f + 1];
  }
  for (int f = 0; f < num_faces; ++f) result.offsets[f + 1] += result.offsets[f];
  result.samples.resize(result.offsets.back());
  std::vector<int> cursor(result.offsets.begin(), result.offsets.end() - 1);
  for (auto& list : per_view) {
    for (const auto& [f, s] : list) result.samples[cursor[f]++] = s;
    list.clear();
    list.shrink_to_fit();
  }
  return result;
}

FaceViewCandidates compute_visibility(const TriangleMesh& mesh,
                                      const MeshTopology& topology,
                                      const std::vector<TextureView>& views,
                                      const TextureOptions& options,
                                      Reporter& reporter) {
  const int num_views = static_cast<int>(views.size());
  std::vector<ViewSamples> per_view(num_views);
  reporter.begin("visibility", num_views);
#pragma omp parallel for schedule(dynamic)
  for (int v = 0; v < num_views; ++v) {
    if (reporter.cancel_requested()) continue;
    per_view[v] = compute_view_visibility(mesh, topology, views[v], v, options);
    reporter.advance();
  }
  reporter.end();
  reporter.throw_if_cancelled();
  return gather_candidates(static_cast<int>(mesh.faces.size()), per_view);
}

}  // namespace hos::texture
