// Two passes per view: a visibility pass (z-buffer of face ids and
// perspective-correct barycentrics, OpenMP over row bands so every sample is
// written by one thread and the result is deterministic), then shading of the
// visible samples. Colour is rendered at s x s samples per pixel and
// box-filtered in linear RGB; depth, mask, normals and ids come from a pass
// whose samples sit exactly on the pixel centres.
#include "render/rasterizer.h"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "render/scan_triangle.h"

namespace hos::render {
namespace {

constexpr double kNear = 1e-4;

float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

float linear_to_srgb(float c) {
  c = std::clamp(c, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

const std::array<float, 256>& srgb_decode_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[i] = srgb_to_linear(static_cast<float>(i) / 255.0f);
    return t;
  }();
  return table;
}

// A triangle after near-plane clipping: pixel-space (scaled) positions, 1/z,
// (double: a clipped vertex near the camera projects far outside the image,
// and float edge functions lose the interior's precision), and the barycentrics of its corners in
// the ORIGINAL face, so interpolation stays in terms of the original vertices' attributes.
struct ScreenTriangle {
  std::array<Eigen::Vector2d, 3> p;
  std::array<double, 3> inv_z;
  std::array<Eigen::Vector3d, 3> bary;
  int face = 0;  // global face index
  int object = 0;
  double xmin, xmax, ymin, ymax;
};

struct CameraFrame {
  Eigen::Matrix3f R;
  Eigen::Vector3f t;
  float fx, fy, cx, cy;
};

// The visible surface at each sample of a (width*scale) x (height*scale) grid.
struct SampleBuffer {
  int width = 0, height = 0;
  std::vector<float> z;   // camera z, +inf when empty
  std::vector<int> face;  // -1 when empty
  std::vector<int> object;
  std::vector<Eigen::Vector3f> bary;  // in the original face
};

void clip_and_project(const std::array<Eigen::Vector3f, 3>& cam,
                      const CameraFrame& frame,
                      float scale,
                      int face,
                      int object,
                      std::vector<ScreenTriangle>& out) {
  struct ClipVertex {
    Eigen::Vector3d x;
    Eigen::Vector3d b;
  };
  std::array<ClipVertex, 3> in{{{cam[0].cast<double>(), Eigen::Vector3d(1, 0, 0)},
                                {cam[1].cast<double>(), Eigen::Vector3d(0, 1, 0)},
                                {cam[2].cast<double>(), Eigen::Vector3d(0, 0, 1)}}};
  std::vector<ClipVertex> poly;
  poly.reserve(4);
  for (int i = 0; i < 3; ++i) {
    const ClipVertex& a = in[i];
    const ClipVertex& b = in[(i + 1) % 3];
    const bool a_in = a.x.z() >= kNear;
    const bool b_in = b.x.z() >= kNear;
    if (a_in) poly.push_back(a);
    if (a_in != b_in) {
      const double s = (kNear - a.x.z()) / (b.x.z() - a.x.z());
      poly.push_back({a.x + s * (b.x - a.x), a.b + s * (b.b - a.b)});
    }
  }
  if (poly.size() < 3) return;
  auto project = [&](const ClipVertex& v) {
    return Eigen::Vector2d((frame.fx * v.x.x() / v.x.z() + frame.cx) * scale,
                           (frame.fy * v.x.y() / v.x.z() + frame.cy) * scale);
  };
  for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
    ScreenTriangle t;
    const ClipVertex* v[3] = {&poly[0], &poly[k], &poly[k + 1]};
    for (int c = 0; c < 3; ++c) {
      t.p[c] = project(*v[c]);
      t.inv_z[c] = 1.0f / v[c]->x.z();
      t.bary[c] = v[c]->b;
    }
    t.face = face;
    t.object = object;
    t.xmin = std::min({t.p[0].x(), t.p[1].x(), t.p[2].x()});
    t.xmax = std::max({t.p[0].x(), t.p[1].x(), t.p[2].x()});
    t.ymin = std::min({t.p[0].y(), t.p[1].y(), t.p[2].y()});
    t.ymax = std::max({t.p[0].y(), t.p[1].y(), t.p[2].y()});
    out.push_back(t);
  }
}

std::vector<ScreenTriangle> setup_triangles(const std::vector<RenderObject>& objects,
                                            const CameraFrame& frame,
                                            float scale,
                                            bool cull_back_faces,
                                            int width,
                                            int height) {
  std::vector<ScreenTriangle> tris;
  int face_offset = 0;
  for (int o = 0; o < static_cast<int>(objects.size()); ++o) {
    const TriangleMesh& mesh = objects[o].mesh;
    std::vector<Eigen::Vector3f> cam(mesh.vertices.size());
    for (std::size_t i = 0; i < cam.size(); ++i) cam[i] = frame.R * mesh.vertices[i] + frame.t;
    for (int f = 0; f < static_cast<int>(mesh.faces.size()); ++f) {
      const Eigen::Vector3i& F = mesh.faces[f];
      const std::array<Eigen::Vector3f, 3> c{cam[F[0]], cam[F[1]], cam[F[2]]};
      // Faces with a non-finite vertex are not drawn (nothing NaN reaches the buffers).
      if (!(c[0].allFinite() && c[1].allFinite() && c[2].allFinite())) continue;
      if (c[0].z() < kNear && c[1].z() < kNear && c[2].z() < kNear) continue;
      if (cull_back_faces && (c[1] - c[0]).cross(c[2] - c[0]).dot(c[0]) >= 0.0f) continue;
      clip_and_project(c, frame, scale, face_offset + f, o, tris);
    }
    face_offset += static_cast<int>(mesh.faces.size());
  }
  // Drop triangles entirely outside the image.
  std::erase_if(tris,
                [&](const ScreenTriangle& t) { return t.xmax < 0 || t.ymax < 0 || t.xmin > width || t.ymin > height; });
  return tris;
}

// Samples are at (x + 0.5, y + 0.5) in the scaled pixel grid.
SampleBuffer rasterize(const std::vector<ScreenTriangle>& tris, int width, int height) {
  SampleBuffer buf;
  buf.width = width;
  buf.height = height;
  const std::size_t n = static_cast<std::size_t>(width) * height;
  buf.z.assign(n, std::numeric_limits<float>::infinity());
  buf.face.assign(n, -1);
  buf.object.assign(n, -1);
  buf.bary.assign(n, Eigen::Vector3f::Zero());
  const int band_height = 16;
  const int num_bands = (height + band_height - 1) / band_height;
#pragma omp parallel for schedule(dynamic, 1)
  for (int band = 0; band < num_bands; ++band) {
    const int y0 = band * band_height;
    const int y1 = std::min(height, y0 + band_height);
    for (const ScreenTriangle& t : tris) {
      if (t.ymax < y0 || t.ymin > y1) continue;
      const Eigen::Vector2d &a = t.p[0], &b = t.p[1], &c = t.p[2];
      const double area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
      if (std::abs(area) < 1e-12) continue;
      const PixelRange range{static_cast<int>(std::max(0.0, std::ceil(t.xmin - 0.5))),
                             static_cast<int>(std::min(width - 1.0, std::floor(t.xmax - 0.5))),
                             static_cast<int>(std::max<double>(y0, std::ceil(t.ymin - 0.5))),
                             static_cast<int>(std::min<double>(y1 - 1, std::floor(t.ymax - 0.5)))};
      scan_triangle(a, b, c, 1.0 / area, range, [&](int x, int y, double w0, double w1, double w2) {
        // Perspective-correct: 1/z and attribute/z are affine in screen space.
        const double iz = w0 * t.inv_z[0] + w1 * t.inv_z[1] + w2 * t.inv_z[2];
        if (!(iz > 0)) return;
        const float z = static_cast<float>(1.0 / iz);
        const std::size_t idx = static_cast<std::size_t>(y) * width + x;
        if (z >= buf.z[idx]) return;
        buf.z[idx] = z;
        buf.face[idx] = t.face;
        buf.object[idx] = t.object;
        buf.bary[idx] = ((w0 * t.inv_z[0] * t.bary[0] + w1 * t.inv_z[1] * t.bary[1] + w2 * t.inv_z[2] * t.bary[2]) / iz)
                            .cast<float>();
      });
    }
  }
  return buf;
}

struct FaceLookup {
  std::vector<int> first_face;  // per object
  int local(int object, int face) const { return face - first_face[object]; }
};

Eigen::Vector3f sample_texture(const cv::Mat& tex, const Eigen::Vector2f& uv) {
  const auto& decode = srgb_decode_table();
  const float x = uv.x() * tex.cols - 0.5f;
  const float y = uv.y() * tex.rows - 0.5f;
  const int x0 = static_cast<int>(std::floor(x));
  const int y0 = static_cast<int>(std::floor(y));
  const float fx = x - x0, fy = y - y0;
  auto texel = [&](int xi, int yi) {
    xi = std::clamp(xi, 0, tex.cols - 1);
    yi = std::clamp(yi, 0, tex.rows - 1);
    const cv::Vec3b& v = tex.at<cv::Vec3b>(yi, xi);
    return Eigen::Vector3f(decode[v[2]], decode[v[1]], decode[v[0]]);
  };
  return (1 - fy) * ((1 - fx) * texel(x0, y0) + fx * texel(x0 + 1, y0)) +
         fy * ((1 - fx) * texel(x0, y0 + 1) + fx * texel(x0 + 1, y0 + 1));
}

Eigen::Vector3f albedo_at(const RenderObject& obj, int f, const Eigen::Vector3f& b, const Eigen::Vector3f& x_world) {
  const Material& m = obj.material;
  const Eigen::Vector3i& F = obj.mesh.faces[f];
  if (!m.textures.empty()) {
    const Eigen::Vector2f uv =
        b[0] * m.corner_uvs[3 * f] + b[1] * m.corner_uvs[3 * f + 1] + b[2] * m.corner_uvs[3 * f + 2];
    const int ti = m.face_texture.empty() ? 0 : m.face_texture[f];
    return sample_texture(m.textures[ti], uv);
  }
  if (m.procedural) return m.procedural(x_world);
  if (!obj.mesh.colors.empty()) {
    const auto& decode = srgb_decode_table();
    Eigen::Vector3f c = Eigen::Vector3f::Zero();
    for (int k = 0; k < 3; ++k) {
      const Rgb8& v = obj.mesh.colors[F[k]];
      c += b[k] * Eigen::Vector3f(decode[v[0]], decode[v[1]], decode[v[2]]);
    }
    return c;
  }
  return m.constant_albedo;
}

Eigen::Vector3f normal_at(const TriangleMesh& mesh, int f, const Eigen::Vector3f& b) {
  const Eigen::Vector3i& F = mesh.faces[f];
  if (!mesh.normals.empty()) {
    const Eigen::Vector3f n = b[0] * mesh.normals[F[0]] + b[1] * mesh.normals[F[1]] + b[2] * mesh.normals[F[2]];
    if (n.squaredNorm() > 1e-20f) return n.normalized();
  }
  const Eigen::Vector3f n =
      (mesh.vertices[F[1]] - mesh.vertices[F[0]]).cross(mesh.vertices[F[2]] - mesh.vertices[F[0]]);
  return n.squaredNorm() > 0 ? n.normalized() : Eigen::Vector3f::UnitZ();
}

void validate_inputs(const std::vector<RenderObject>& objects, const Camera& camera, const RenderOptions& options) {
  if (camera.width <= 0 || camera.height <= 0) throw std::invalid_argument("render_view: empty camera");
  if (options.supersampling < 1) throw std::invalid_argument("render_view: supersampling must be >= 1");
  for (const RenderObject& o : objects) {
    const Material& m = o.material;
    if (m.textures.empty()) continue;
    if (m.corner_uvs.size() != 3 * o.mesh.faces.size())
      throw std::invalid_argument("render_view: corner_uvs must have 3 entries per face");
    if (!m.face_texture.empty() && m.face_texture.size() != o.mesh.faces.size())
      throw std::invalid_argument("render_view: face_texture must have one entry per face");
    for (const int t : m.face_texture)
      if (t < 0 || t >= static_cast<int>(m.textures.size()))
        throw std::invalid_argument("render_view: face_texture index out of range");
    for (const cv::Mat& tex : m.textures)
      if (tex.type() != CV_8UC3 || tex.empty())
        throw std::invalid_argument("render_view: textures must be non-empty CV_8UC3");
  }
}

CameraFrame camera_frame(const Camera& camera, const ImageRecord& pose) {
  CameraFrame frame;
  frame.R = pose.rotation().cast<float>();
  frame.t = pose.cam_from_world_translation.cast<float>();
  frame.fx = static_cast<float>(camera.focal_x());
  frame.fy = static_cast<float>(camera.focal_y());
  frame.cx = static_cast<float>(camera.principal_x());
  frame.cy = static_cast<float>(camera.principal_y());
  return frame;
}

FaceLookup face_lookup(const std::vector<RenderObject>& objects) {
  FaceLookup lookup;
  int total = 0;
  for (const RenderObject& o : objects) {
    lookup.first_face.push_back(total);
    total += static_cast<int>(o.mesh.faces.size());
  }
  return lookup;
}

// Depth, coverage, normal and face/object ids at the pixel centres.
void write_geometry(const std::vector<RenderObject>& objects,
                    const FaceLookup& lookup,
                    const SampleBuffer& centre,
                    int W,
                    int H,
                    RenderedView& view) {
  view.depth = cv::Mat(H, W, CV_32F, cv::Scalar(0));
  view.mask = cv::Mat(H, W, CV_8U, cv::Scalar(0));
  view.normal = cv::Mat(H, W, CV_32FC3, cv::Scalar::all(0));
  view.face_id = cv::Mat(H, W, CV_32S, cv::Scalar(-1));
  view.object_id = cv::Mat(H, W, CV_32S, cv::Scalar(-1));
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * W + x;
      if (centre.face[i] < 0) continue;
      view.depth.at<float>(y, x) = centre.z[i];
      view.mask.at<std::uint8_t>(y, x) = 255;
      view.face_id.at<int>(y, x) = centre.face[i];
      view.object_id.at<int>(y, x) = centre.object[i];
      const int o = centre.object[i];
      const Eigen::Vector3f n = normal_at(objects[o].mesh, lookup.local(o, centre.face[i]), centre.bary[i]);
      view.normal.at<cv::Vec3f>(y, x) = cv::Vec3f(n.x(), n.y(), n.z());
    }
  }
}

// The colour image from s x s samples per pixel (box filter in linear RGB);
// shade(object, face, barycentric) gives a sample's linear colour.
template <typename Shade>
cv::Mat box_filtered_colour(
    const SampleBuffer& samples, int W, int H, int s, const Eigen::Vector3f& background, const Shade& shade) {
  cv::Mat colour(H, W, CV_8UC3);
#pragma omp parallel for schedule(dynamic, 4)
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      Eigen::Vector3f sum = Eigen::Vector3f::Zero();
      for (int sy = 0; sy < s; ++sy) {
        for (int sx = 0; sx < s; ++sx) {
          const std::size_t i = static_cast<std::size_t>(y * s + sy) * samples.width + (x * s + sx);
          sum += samples.face[i] < 0 ? background : shade(samples.object[i], samples.face[i], samples.bary[i]);
        }
      }
      sum /= static_cast<float>(s * s);
      colour.at<cv::Vec3b>(y, x) = cv::Vec3b(static_cast<std::uint8_t>(std::lround(255.0f * linear_to_srgb(sum.z()))),
                                             static_cast<std::uint8_t>(std::lround(255.0f * linear_to_srgb(sum.y()))),
                                             static_cast<std::uint8_t>(std::lround(255.0f * linear_to_srgb(sum.x()))));
    }
  }
  return colour;
}

}  // namespace

RenderedView render_view(const std::vector<RenderObject>& objects,
                         const Camera& camera,
                         const ImageRecord& pose,
                         const RenderOptions& options) {
  validate_inputs(objects, camera, options);
  const int W = camera.width, H = camera.height, s = options.supersampling;
  const CameraFrame frame = camera_frame(camera, pose);
  const FaceLookup lookup = face_lookup(objects);

  const Eigen::Vector3f light = options.lighting.direction_to_light.normalized();
  const Eigen::Vector3f cam_center = -frame.R.transpose() * frame.t;
  // Linear, exposed colour of the surface seen at one sample.
  auto shade = [&](int object, int face, const Eigen::Vector3f& b) -> Eigen::Vector3f {
    const RenderObject& obj = objects[object];
    const int f = lookup.local(object, face);
    const Eigen::Vector3i& F = obj.mesh.faces[f];
    const Eigen::Vector3f x =
        b[0] * obj.mesh.vertices[F[0]] + b[1] * obj.mesh.vertices[F[1]] + b[2] * obj.mesh.vertices[F[2]];
    Eigen::Vector3f c = albedo_at(obj, f, b, x);
    if (!options.lighting.unlit) {
      Eigen::Vector3f n = normal_at(obj.mesh, f, b);
      // Two-sided: a face seen from behind is lit as its visible side.
      if (n.dot(cam_center - x) < 0) n = -n;
      c *= options.lighting.ambient + options.lighting.diffuse * std::max(0.0f, n.dot(light));
    }
    return c * options.exposure_gain;
  };

  RenderedView view;
  const SampleBuffer centre = rasterize(setup_triangles(objects, frame, 1.0f, options.cull_back_faces, W, H), W, H);
  write_geometry(objects, lookup, centre, W, H, view);
  SampleBuffer super;
  const SampleBuffer* samples = &centre;
  if (s > 1) {
    super = rasterize(setup_triangles(objects, frame, static_cast<float>(s), options.cull_back_faces, W * s, H * s),
                      W * s, H * s);
    samples = &super;
  }
  view.color = box_filtered_colour(*samples, W, H, s, options.background * options.exposure_gain, shade);
  return view;
}

}  // namespace hos::render
