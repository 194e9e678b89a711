#include "tests/texture/scene_fixtures.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "core/colmap_io.h"
#include "synth/shapes.h"
#include "texture/texture_mesh.h"

namespace hos::texture::testing {

void write_sphere_workspace(const std::filesystem::path& folder, int num_views) {
  std::filesystem::create_directories(folder / "images");
  SparseModel model;
  model.cameras[1] = Camera::pinhole(1, 320, 240, 300.0, 300.0, 160.0, 120.0);
  for (int i = 0; i < num_views; ++i) {
    std::string name = "view";
    name += std::to_string(i) + ".png";
    TextureView view = make_view(name, 360.0 / num_views * i, i % 2 ? 30.0 : -30.0, 3.5);
    render_sphere(view, 1.0);
    if (!cv::imwrite((folder / "images" / name).string(), view.image)) {
      throw std::runtime_error("cannot write " + (folder / "images" / name).string());
    }
    ImageRecord record = view.pose;
    record.id = i + 1;
    record.camera_id = 1;
    record.name = name;
    model.images[record.id] = record;
  }
  write_colmap_model(model, folder / "sparse", ColmapFormat::kText);
}

std::string view_name(int i) {
  // Appended rather than "v" + ...: GCC 12 warns (-Wrestrict) on the latter.
  std::string name = "v";
  name += std::to_string(i);
  return name;
}

Eigen::Vector3f sphere_albedo(const Eigen::Vector3f& x) {
  const float a = std::sin(6.0f * x.z() + 2.0f * x.x());
  const float b = std::cos(5.0f * x.x() - 3.0f * x.y());
  return {0.35f + 0.15f * a, 0.45f + 0.25f * b, 0.5f + 0.2f * a * b};
}

TextureView make_view(const std::string& name,
                      double azimuth_deg,
                      double elevation_deg,
                      double distance,
                      int width,
                      int height,
                      double focal) {
  const double az = azimuth_deg * M_PI / 180.0, el = elevation_deg * M_PI / 180.0;
  const Eigen::Vector3d center =
      distance * Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  const Eigen::Vector3d forward = (-center).normalized();
  Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ());
  if (right.norm() < 1e-6) right = Eigen::Vector3d::UnitX();
  right.normalize();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Matrix3d r;  // rows: camera axes in world coordinates
  r.row(0) = right;
  r.row(1) = down;
  r.row(2) = forward;
  TextureView view;
  view.name = name;
  view.camera = Camera::pinhole(1, width, height, focal, focal, width / 2.0, height / 2.0);
  view.pose.name = name;
  view.pose.cam_from_world_rotation = Eigen::Quaterniond(r);
  view.pose.cam_from_world_translation = -r * center;
  view.image = cv::Mat(height, width, CV_8UC3, cv::Scalar(0, 0, 0));
  return view;
}

namespace {

std::optional<double> hit_sphere(const Eigen::Vector3d& origin,
                                 const Eigen::Vector3d& dir,
                                 const Eigen::Vector3d& center,
                                 double radius) {
  const Eigen::Vector3d oc = origin - center;
  const double b = oc.dot(dir);
  const double c = oc.squaredNorm() - radius * radius;
  const double disc = b * b - c;
  if (disc < 0.0) return std::nullopt;
  const double t = -b - std::sqrt(disc);
  if (t <= 0.0) return std::nullopt;
  return t;
}

}  // namespace

void render_sphere(TextureView& view, double radius, float gain, const std::optional<Occluder>& occluder) {
  const Eigen::Vector3d origin = view.pose.center();
  const int ss = 2;  // supersampling per axis
  for (int y = 0; y < view.image.rows; ++y) {
    for (int x = 0; x < view.image.cols; ++x) {
      Eigen::Vector3f sum = Eigen::Vector3f::Zero();
      for (int sy = 0; sy < ss; ++sy) {
        for (int sx = 0; sx < ss; ++sx) {
          const Eigen::Vector2d pixel(x + (sx + 0.5) / ss, y + (sy + 0.5) / ss);
          const Eigen::Vector3d ray_cam((pixel.x() - view.camera.principal_x()) / view.camera.focal_x(),
                                        (pixel.y() - view.camera.principal_y()) / view.camera.focal_y(), 1.0);
          const Eigen::Vector3d dir = (view.pose.rotation().transpose() * ray_cam).normalized();
          const auto t = hit_sphere(origin, dir, Eigen::Vector3d::Zero(), radius);
          std::optional<double> t_occ;
          if (occluder) t_occ = hit_sphere(origin, dir, occluder->center, occluder->radius);
          if (t_occ && (!t || *t_occ < *t)) {
            sum += 255.0f * occluder->rgb;
          } else if (t) {
            sum += 255.0f * gain * sphere_albedo((origin + *t * dir).cast<float>());
          }
        }
      }
      sum /= static_cast<float>(ss * ss);
      auto c8 = [](float v) { return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L)); };
      view.image.at<cv::Vec3b>(y, x) = cv::Vec3b(c8(sum.z()), c8(sum.y()), c8(sum.x()));
    }
  }
}

Eigen::Vector3f sample_atlas(const cv::Mat& atlas, const Eigen::Vector2f& uv) {
  return sample_rgb(atlas, uv.x() * atlas.cols, uv.y() * atlas.rows);
}

std::vector<TexturePoint> texture_points(const TexturedMesh& mesh) {
  std::vector<TexturePoint> points;
  const Eigen::Vector3f weights[4] = {
      {1 / 3.f, 1 / 3.f, 1 / 3.f}, {0.6f, 0.2f, 0.2f}, {0.2f, 0.6f, 0.2f}, {0.2f, 0.2f, 0.6f}};
  for (std::size_t page = 0; page < mesh.indices.size(); ++page) {
    const auto& idx = mesh.indices[page];
    for (std::size_t i = 0; i + 2 < idx.size(); i += 3) {
      const std::uint32_t a = idx[i], b = idx[i + 1], c = idx[i + 2];
      const bool flat = mesh.uvs[a] == mesh.uvs[b] && mesh.uvs[b] == mesh.uvs[c];
      for (const auto& w : weights) {
        TexturePoint p;
        p.page = static_cast<int>(page);
        p.uv = w[0] * mesh.uvs[a] + w[1] * mesh.uvs[b] + w[2] * mesh.uvs[c];
        p.position = w[0] * mesh.positions[a] + w[1] * mesh.positions[b] + w[2] * mesh.positions[c];
        p.flat = flat;
        points.push_back(p);
      }
    }
  }
  return points;
}

void render_textured(const TexturedMesh& mesh, const TextureView& view, cv::Mat& image, cv::Mat& mask) {
  const int w = view.camera.width, h = view.camera.height;
  image = cv::Mat(h, w, CV_8UC3, cv::Scalar(0, 0, 0));
  mask = cv::Mat(h, w, CV_8U, cv::Scalar(0));
  cv::Mat depth(h, w, CV_32F, cv::Scalar(std::numeric_limits<float>::infinity()));
  std::vector<Eigen::Vector3d> p(mesh.positions.size());
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = view.project(mesh.positions[i].cast<double>());
  for (std::size_t page = 0; page < mesh.indices.size(); ++page) {
    const auto& idx = mesh.indices[page];
    for (std::size_t t = 0; t + 2 < idx.size(); t += 3) {
      const Eigen::Vector3d& a = p[idx[t]];
      const Eigen::Vector3d& b = p[idx[t + 1]];
      const Eigen::Vector3d& c = p[idx[t + 2]];
      if (a.z() <= 0 || b.z() <= 0 || c.z() <= 0) continue;
      const double area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
      if (std::abs(area) < 1e-12) continue;
      const int x0 = std::max(0, static_cast<int>(std::min({a.x(), b.x(), c.x()})));
      const int x1 = std::min(w - 1, static_cast<int>(std::max({a.x(), b.x(), c.x()})));
      const int y0 = std::max(0, static_cast<int>(std::min({a.y(), b.y(), c.y()})));
      const int y1 = std::min(h - 1, static_cast<int>(std::max({a.y(), b.y(), c.y()})));
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          const double px = x + 0.5, py = y + 0.5;
          const double wa = ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) / area;
          const double wb = ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) / area;
          const double wc = 1.0 - wa - wb;
          if (wa < 0 || wb < 0 || wc < 0) continue;
          // Perspective-correct interpolation: weights / z, renormalized.
          const double pa = wa / a.z(), pb = wb / b.z(), pc = wc / c.z();
          const double z = 1.0 / (pa + pb + pc);
          if (z >= depth.at<float>(y, x)) continue;
          depth.at<float>(y, x) = static_cast<float>(z);
          const Eigen::Vector2f uv = static_cast<float>(pa * z) * mesh.uvs[idx[t]] +
                                     static_cast<float>(pb * z) * mesh.uvs[idx[t + 1]] +
                                     static_cast<float>(pc * z) * mesh.uvs[idx[t + 2]];
          const Eigen::Vector3f rgb = sample_atlas(mesh.atlases[page], uv);
          image.at<cv::Vec3b>(y, x) = cv::Vec3b(cv::saturate_cast<uchar>(rgb.z()), cv::saturate_cast<uchar>(rgb.y()),
                                                cv::saturate_cast<uchar>(rgb.x()));
          mask.at<std::uint8_t>(y, x) = 255;
        }
      }
    }
  }
}

std::vector<TextureView> six_views_of_sphere(double elevation_deg) {
  std::vector<TextureView> views;
  for (int i = 0; i < 6; ++i) {
    views.push_back(make_view(view_name(i), 60.0 * i, elevation_deg, 3.5));
    render_sphere(views.back(), 1.0);
  }
  return views;
}

TexturedMesh textured_sphere(int atlas_size) {
  TextureOptions options;
  options.atlas_size = atlas_size;
  return texture_mesh(synth::icosphere(3, 1.0), six_views_of_sphere(10.0), options, null_reporter()).mesh;
}

MeshTopology strip_topology(int n) {
  MeshTopology t;
  t.face_neighbors.assign(n, {-1, -1, -1});
  for (int i = 0; i < n; ++i) {
    if (i > 0) t.face_neighbors[i][0] = i - 1;
    if (i + 1 < n) t.face_neighbors[i][1] = i + 1;
  }
  return t;
}

}  // namespace hos::texture::testing
