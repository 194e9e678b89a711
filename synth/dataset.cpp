#include "synth/dataset.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/colmap_io.h"
#include "core/error.h"
#include "core/ply_io.h"
#include "synth/geo_tags.h"
#include "synth/synth_options.h"

namespace hos::synth {
namespace fs = std::filesystem;
namespace {

ImageRecord look_at(int id, const Eigen::Vector3d& centre, const Eigen::Vector3d& target, const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = (target - centre).normalized();
  const Eigen::Vector3d x = (-up).cross(z).normalized();  // -up is the camera's y (down)
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R.row(0) = x;
  R.row(1) = y;
  R.row(2) = z;
  ImageRecord image;
  image.id = id;
  image.camera_id = 1;
  image.cam_from_world_rotation = Eigen::Quaterniond(R).normalized();
  image.cam_from_world_translation = -R * centre;
  return image;
}

// The camera turned about its x axis, its view up by tilt_deg (its centre
// kept): the rotation by -tilt about x takes its z axis towards -y, up.
ImageRecord tilted(ImageRecord image, double tilt_deg) {
  if (tilt_deg == 0.0) return image;
  const Eigen::Vector3d centre = image.center();
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(-tilt_deg * std::numbers::pi / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Matrix3d rotation = turn * image.rotation();
  image.cam_from_world_rotation = Eigen::Quaterniond(rotation).normalized();
  image.cam_from_world_translation = -rotation * centre;
  return image;
}

// Camera centre at the given elevation (above the horizon) and azimuth.
Eigen::Vector3d ring_position(const Scene& scene, double distance, double elevation, double azimuth) {
  const Eigen::Vector3d up = scene.up.cast<double>();
  // Two horizontal axes orthogonal to up.
  const Eigen::Vector3d a = up.unitOrthogonal();
  const Eigen::Vector3d b = up.cross(a);
  const Eigen::Vector3d dir =
      std::cos(elevation) * (std::cos(azimuth) * a + std::sin(azimuth) * b) + std::sin(elevation) * up;
  return scene.centre.cast<double>() + distance * dir;
}

// The smallest distance from the scene centre at which every object vertex
// projects inside the image with a margin, for a camera looking at the centre
// from this direction: with (X, Y, Z) a vertex in the frame of a camera at the
// centre, the vertex at distance D has depth Z + D and needs
// |X| f / (Z + D) <= w/2 - margin, so D >= |X| f / (w/2 - margin) - Z (same for Y).
double fit_distance(const Scene& scene, const ImageRecord& at_centre, const Camera& camera) {
  const double margin = 0.06;
  const double hw = (1 - margin) * 0.5 * camera.width, hh = (1 - margin) * 0.5 * camera.height;
  double d = 0;
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    if (scene.is_ground[o]) continue;
    for (const Eigen::Vector3f& v : scene.objects[o].mesh.vertices) {
      const Eigen::Vector3d x = at_centre.cam_from_world(v.cast<double>());
      d = std::max(
          {d, std::abs(x.x()) * camera.focal_x() / hw - x.z(), std::abs(x.y()) * camera.focal_y() / hh - x.z()});
    }
  }
  // Never inside the bounding sphere.
  return std::max(d, 1.2 * scene.radius);
}

double focal_of(const DatasetOptions& o) { return o.focal > 0 ? o.focal : 0.9 * o.width; }

Camera make_camera(const DatasetOptions& o) {
  const double f = focal_of(o);
  return Camera::pinhole(1, o.width, o.height, f, f, 0.5 * o.width, 0.5 * o.height);
}

// Area-weighted random surface points of all objects, with their normals.
struct SurfaceSampler {
  std::vector<std::pair<int, int>> faces;  // (object, face)
  std::vector<double> cumulative;
  const Scene& scene;
  explicit SurfaceSampler(const Scene& s) : scene(s) {
    double total = 0;
    for (int o = 0; o < static_cast<int>(s.objects.size()); ++o) {
      const TriangleMesh& m = s.objects[o].mesh;
      for (int f = 0; f < static_cast<int>(m.faces.size()); ++f) {
        const Eigen::Vector3i& F = m.faces[f];
        total += 0.5 * (m.vertices[F[1]] - m.vertices[F[0]]).cross(m.vertices[F[2]] - m.vertices[F[0]]).norm();
        faces.emplace_back(o, f);
        cumulative.push_back(total);
      }
    }
  }
  Eigen::Vector3d sample(std::mt19937& rng) const {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double r = u(rng) * cumulative.back();
    const std::size_t i = std::min(
        faces.size() - 1,
        static_cast<std::size_t>(std::lower_bound(cumulative.begin(), cumulative.end(), r) - cumulative.begin()));
    const TriangleMesh& m = scene.objects[faces[i].first].mesh;
    const Eigen::Vector3i& F = m.faces[faces[i].second];
    double s = u(rng), t = u(rng);
    if (s + t > 1) s = 1 - s, t = 1 - t;
    return (m.vertices[F[0]] + s * (m.vertices[F[1]] - m.vertices[F[0]]) + t * (m.vertices[F[2]] - m.vertices[F[0]]))
        .cast<double>();
  }
};

void add_sparse_points(const Scene& scene,
                       const std::vector<render::RenderedView>& views,
                       int target,
                       SparseModel& model) {
  if (scene.objects.empty() || target <= 0) return;
  SurfaceSampler sampler(scene);
  std::mt19937 rng(12345);
  std::vector<ImageRecord*> images;
  for (auto& [id, image] : model.images) images.push_back(&image);
  const Camera& camera = model.cameras.begin()->second;
  std::int64_t next_id = 1;
  for (int attempt = 0; attempt < 20 * target && static_cast<int>(model.points.size()) < target; ++attempt) {
    const Eigen::Vector3d X = sampler.sample(rng);
    std::vector<std::pair<int, Eigen::Vector2d>> seen;
    for (std::size_t k = 0; k < images.size(); ++k) {
      const Eigen::Vector3d xc = images[k]->cam_from_world(X);
      const auto p = camera.project(xc);
      if (!p || (*p).x() < 0 || (*p).y() < 0 || (*p).x() >= camera.width || (*p).y() >= camera.height) continue;
      const float d = views[k].depth.at<float>(static_cast<int>((*p).y()), static_cast<int>((*p).x()));
      if (d <= 0 || std::abs(d - xc.z()) > 0.01 * xc.z()) continue;
      seen.emplace_back(static_cast<int>(k), *p);
    }
    if (seen.size() < 2) continue;
    Point3D point;
    point.id = next_id++;
    point.xyz = X;
    const cv::Vec3b c = views[seen[0].first].color.at<cv::Vec3b>(static_cast<int>(seen[0].second.y()),
                                                                 static_cast<int>(seen[0].second.x()));
    point.color = {c[2], c[1], c[0]};
    for (const auto& [k, xy] : seen) {
      ImageRecord& image = *images[k];
      point.track.push_back({image.id, static_cast<int>(image.keypoints.size())});
      image.keypoints.push_back({xy, point.id});
    }
    model.points.emplace(point.id, std::move(point));
  }
}

void write_image(const fs::path& path, const cv::Mat& image) {
  bool ok = false;
  try {
    ok = cv::imwrite(path.string(), image);
  } catch (const cv::Exception& e) {
    throw OutputError(path.string(), e.what());
  }
  if (!ok) throw OutputError(path.string(), "the image");
}

nlohmann::json vec_json(const Eigen::Vector3f& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

cv::Mat encode_normal_map(const cv::Mat& normals) {
  cv::Mat out(normals.size(), CV_16UC3, cv::Scalar::all(0));
  for (int y = 0; y < normals.rows; ++y)
    for (int x = 0; x < normals.cols; ++x) {
      const cv::Vec3f& n = normals.at<cv::Vec3f>(y, x);
      if (n == cv::Vec3f(0, 0, 0)) continue;
      auto q = [](float v) {
        return static_cast<std::uint16_t>(std::lround((std::clamp(v, -1.0f, 1.0f) + 1.0f) * 0.5f * 65535.0f));
      };
      out.at<cv::Vec3w>(y, x) = cv::Vec3w(q(n[2]), q(n[1]), q(n[0]));  // BGR order: the file's RGB is xyz
    }
  return out;
}

cv::Mat decode_normal_map(const cv::Mat& encoded) {
  if (encoded.type() != CV_16UC3) throw std::invalid_argument("decode_normal_map: expected a 16-bit 3-channel image");
  cv::Mat out(encoded.size(), CV_32FC3, cv::Scalar::all(0));
  for (int y = 0; y < encoded.rows; ++y)
    for (int x = 0; x < encoded.cols; ++x) {
      const cv::Vec3w& v = encoded.at<cv::Vec3w>(y, x);
      if (v == cv::Vec3w(0, 0, 0)) continue;
      auto d = [](std::uint16_t q) { return q / 65535.0f * 2.0f - 1.0f; };
      out.at<cv::Vec3f>(y, x) = cv::Vec3f(d(v[2]), d(v[1]), d(v[0]));
    }
  return out;
}

std::string view_name(int index, bool jpeg) {
  std::ostringstream s;
  s << "view_" << std::setw(3) << std::setfill('0') << index << (jpeg ? ".jpg" : ".png");
  return s.str();
}

void DatasetOptions::validate() const {
  check_option_table("synth", *this);
  // The rules the table cannot hold: lists and two options.
  if (!exposure_gains.empty() && static_cast<int>(exposure_gains.size()) != num_views)
    throw ConfigError("exposure_gains", "needs one gain per view");
  if (gps_origin && !jpeg) throw ConfigError("gps", "GPS EXIF needs JPEG views (--jpeg)");
  if (masked_views > num_views) throw ConfigError("masked_views", "is more than the views");
  for (const float g : exposure_gains)
    if (!(g > 0) || !std::isfinite(g)) throw ConfigError("exposure_gains", "gains must be positive");
}

Camera dataset_camera(const DatasetOptions& o) { return make_camera(o); }

ImageRecord view_towards_centre(const Scene& scene, const Camera& camera, double elevation, double azimuth) {
  const Eigen::Vector3d target = scene.centre.cast<double>();
  const Eigen::Vector3d up = scene.up.cast<double>();
  // The orientation does not depend on the distance: fit with the camera at the centre.
  ImageRecord probe = look_at(0, ring_position(scene, 1.0, elevation, azimuth), target, up);
  probe.cam_from_world_translation = -(probe.rotation() * target);
  const double distance = fit_distance(scene, probe, camera);
  return look_at(0, ring_position(scene, distance, elevation, azimuth), target, up);
}

namespace {

// Directions (elevation, azimuth) of the training views, then of the held-out
// views: between the rings in elevation and between the views in azimuth.
std::vector<std::pair<double, double>> view_directions(const DatasetOptions& o) {
  std::vector<std::pair<double, double>> dirs;
  for (int r = 0; r < o.rings; ++r) {
    const int count = o.num_views / o.rings + (r < o.num_views % o.rings ? 1 : 0);
    const double elevation = (o.rings == 1 ? 30.0 : 15.0 + 35.0 * r / (o.rings - 1)) * std::numbers::pi / 180.0;
    const double offset = r * std::numbers::pi / std::max(1, count);  // rings staggered
    for (int k = 0; k < count; ++k) dirs.emplace_back(elevation, offset + 2 * std::numbers::pi * k / count);
  }
  for (int k = 0; k < o.holdout; ++k)
    dirs.emplace_back(27.0 * std::numbers::pi / 180.0, 2 * std::numbers::pi * (k + 0.37) / o.holdout);
  return dirs;
}

// All cameras (training then held-out), each as close as keeps every object
// in its frame (so the objects fill the photos; distances differ per view).
std::vector<ImageRecord> place_cameras(const Scene& scene, const DatasetOptions& o, const Camera& camera) {
  std::vector<ImageRecord> images;
  for (const auto& [elevation, azimuth] : view_directions(o)) {
    images.push_back(tilted(view_towards_centre(scene, camera, elevation, azimuth), o.tilt_deg));
  }
  return images;
}

}  // namespace

SparseModel make_cameras(const Scene& scene, const DatasetOptions& o) {
  o.validate();
  SparseModel model;
  const Camera camera = make_camera(o);
  model.cameras.emplace(1, camera);
  std::vector<ImageRecord> images = place_cameras(scene, o, camera);
  for (int k = 0; k < o.num_views; ++k) {
    ImageRecord& image = images[k];
    image.id = k + 1;
    image.name = view_name(k, o.jpeg);
    model.images.emplace(image.id, std::move(image));
  }
  return model;
}

namespace {

SparseModel make_holdout_cameras(const Scene& scene, const DatasetOptions& o) {
  SparseModel model;
  const Camera camera = make_camera(o);
  model.cameras.emplace(1, camera);
  std::vector<ImageRecord> images = place_cameras(scene, o, camera);
  for (int k = 0; k < o.holdout; ++k) {
    ImageRecord& image = images[o.num_views + k];
    image.id = k + 1;
    image.name = view_name(k, o.jpeg);
    model.images.emplace(image.id, std::move(image));
  }
  return model;
}

}  // namespace

RenderedDataset render_dataset(const Scene& scene, const DatasetOptions& o, Reporter& reporter) {
  o.validate();
  RenderedDataset data;
  data.model = make_cameras(scene, o);
  const Camera& camera = data.model.cameras.at(1);
  render::RenderOptions render_options;
  render_options.supersampling = o.supersampling;
  reporter.begin("rendering", o.num_views + o.holdout);
  for (const auto& [id, image] : data.model.images) {
    reporter.throw_if_cancelled();
    render_options.exposure_gain = o.exposure_gains.empty() ? 1.0f : o.exposure_gains[id - 1];
    data.views.push_back(render::render_view(scene.objects, camera, image, render_options));
    reporter.advance();
  }
  render_options.exposure_gain = 1.0f;
  data.holdout = make_holdout_cameras(scene, o);
  for (const auto& [id, image] : data.holdout.images) {
    reporter.throw_if_cancelled();
    data.holdout_views.push_back(render::render_view(scene.objects, camera, image, render_options));
    reporter.advance();
  }
  reporter.end();
  add_sparse_points(scene, data.views, o.num_points, data.model);
  return data;
}

namespace {

// scene.json: the scene's objects, bounds, lighting and the capture's
// settings, for the tests and benchmarks that read the truth.
nlohmann::json scene_description(const Scene& scene,
                                 const SceneOptions& scene_options,
                                 const DatasetOptions& o,
                                 std::size_t sparse_points) {
  BoundingBox box;
  nlohmann::json objects = nlohmann::json::array();
  for (std::size_t k = 0; k < scene.objects.size(); ++k) {
    BoundingBox b;
    for (const Eigen::Vector3f& v : scene.objects[k].mesh.vertices) b.extend(v);
    if (!scene.is_ground[k]) box.extend(b.min), box.extend(b.max);
    objects.push_back({{"name", scene.names[k]},
                       {"ground", static_cast<bool>(scene.is_ground[k])},
                       {"vertices", scene.objects[k].mesh.num_vertices()},
                       {"faces", scene.objects[k].mesh.num_faces()},
                       {"bbox_min", vec_json(b.min)},
                       {"bbox_max", vec_json(b.max)}});
  }
  const render::Lighting lighting;
  nlohmann::json gps_origin;  // null without GPS
  if (o.gps_origin) {
    gps_origin = {{"latitude_deg", o.gps_origin->latitude_deg},
                  {"longitude_deg", o.gps_origin->longitude_deg},
                  {"altitude_m", o.gps_origin->altitude_m.value_or(0.0)}};
  }
  return {{"seed", scene_options.seed},
          {"scene", scene_options.name},
          {"ground_plane", scene_options.ground_plane},
          {"hanging_object", scene_options.hanging_object},
          {"objects", objects},
          {"bbox_min", vec_json(box.min)},
          {"bbox_max", vec_json(box.max)},
          {"diagonal", box.diagonal()},
          {"centre", vec_json(scene.centre)},
          {"radius", scene.radius},
          {"up", vec_json(scene.up)},
          {"light_direction", vec_json(lighting.direction_to_light.normalized())},
          {"ambient", lighting.ambient},
          {"diffuse", lighting.diffuse},
          {"views", o.num_views},
          {"holdout", o.holdout},
          {"width", o.width},
          {"height", o.height},
          {"focal", focal_of(o)},
          {"supersampling", o.supersampling},
          {"exposure_gains", o.exposure_gains},
          {"tilt_deg", o.tilt_deg},
          {"gps_origin", gps_origin},
          {"metres_per_unit", o.metres_per_unit},
          {"sparse_points", sparse_points}};
}

}  // namespace

namespace {

// The box a masked view's passer-by covers: a fifth of the width, half the
// height, left of the centre, where the objects are.
cv::Rect passer_by_box(cv::Size size) {
  return {size.width * 3 / 10, size.height / 4, size.width / 5, size.height / 2};
}

cv::Mat with_passer_by(const cv::Mat& photo) {
  cv::Mat out = photo.clone();
  out(passer_by_box(photo.size())).setTo(cv::Scalar(255, 0, 255));
  return out;
}

// Black (masked) over the box and a 2-pixel margin, white elsewhere.
cv::Mat passer_by_mask(cv::Size size) {
  cv::Mat mask(size, CV_8U, cv::Scalar(255));
  const cv::Rect box = passer_by_box(size);
  const cv::Rect grown(box.x - 2, box.y - 2, box.width + 4, box.height + 4);
  mask(grown & cv::Rect(0, 0, size.width, size.height)).setTo(0);
  return mask;
}

}  // namespace

void write_dataset(const fs::path& folder,
                   const Scene& scene,
                   const SceneOptions& scene_options,
                   const DatasetOptions& o,
                   Reporter& reporter) {
  // The folder is replaced as a whole: never delete a folder hos-synth did not write.
  if (fs::exists(folder) && !(fs::is_directory(folder) && (fs::is_empty(folder) || fs::exists(folder / "scene.json"))))
    throw OutputError(folder.string(), "exists and is not a hos-synth output; refusing to replace it");
  const RenderedDataset data = render_dataset(scene, o, reporter);
  write_folder_atomically(folder, [&](const fs::path& tmp) {
    fs::create_directories(tmp / "images");
    if (o.masked_views > 0) fs::create_directories(tmp / "masks");
    std::size_t i = 0;
    for (const auto& [id, image] : data.model.images) {
      const bool masked = static_cast<int>(i) < o.masked_views;
      write_image(tmp / "images" / image.name, masked ? with_passer_by(data.views[i].color) : data.views[i].color);
      if (masked) write_image(tmp / "masks" / (image.name + ".png"), passer_by_mask(data.views[i].color.size()));
      ++i;
      if (o.gps_origin) {
        write_gps_exif(tmp / "images" / image.name,
                       scene_gps_position(image.center(), *o.gps_origin, o.metres_per_unit));
      }
    }
    write_colmap_model(data.model, tmp / "sparse", ColmapFormat::kText);
    auto stem = [](std::size_t k) { return fs::path(view_name(static_cast<int>(k), false)).stem().string(); };
    if (o.write_depth) {
      fs::create_directories(tmp / "depth");
      for (std::size_t k = 0; k < data.views.size(); ++k)
        write_image(tmp / "depth" / (stem(k) + ".tiff"), data.views[k].depth);
    }
    // Not a float TIFF: OpenCV stores 3-channel float TIFFs as lossy LogLuv.
    if (o.write_normals) {
      fs::create_directories(tmp / "normals");
      for (std::size_t k = 0; k < data.views.size(); ++k)
        write_image(tmp / "normals" / (stem(k) + ".png"), encode_normal_map(data.views[k].normal));
    }
    if (o.holdout > 0) {
      fs::create_directories(tmp / "holdout" / "images");
      std::size_t k = 0;
      for (const auto& [id, image] : data.holdout.images)
        write_image(tmp / "holdout" / "images" / image.name, data.holdout_views[k++].color);
      write_colmap_model(data.holdout, tmp / "holdout" / "sparse", ColmapFormat::kText);
    }
    write_mesh_ply(tmp / "gt_mesh.ply", merged_mesh(scene, true));
    write_mesh_ply(tmp / "gt_objects.ply", merged_mesh(scene, false));

    const nlohmann::json json = scene_description(scene, scene_options, o, data.model.points.size());
    std::ofstream out(tmp / "scene.json");
    out << json.dump(2) << "\n";
    if (!out) throw OutputError((folder / "scene.json").string(), "the scene description");
  });
}

}  // namespace hos::synth
