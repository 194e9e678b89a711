// Benchmark of the texture stage: time and peak memory of every step on a
// synthetic scene (a bumpy lat-long sphere of a chosen face count, photographed
// by ray casting from views on rings around it).
//
//   hos-texture-bench --faces 1000000 --views 50 [--width 1280 --height 960] [--output x.glb]
//
// Peak memory per step: the reporter resets the kernel's peak-RSS counter
// (/proc/self/clear_refs, "5") at the start of each step and reads VmHWM at its end.
#include <omp.h>

#include <CLI/CLI.hpp>
#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <string>

#include "texture/gltf_writer.h"
#include "texture/texture_mesh.h"

namespace {

long read_status_kb(const std::string& key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key + ":", 0) == 0) return std::stol(line.substr(key.size() + 1));
  }
  return -1;
}

void reset_peak() {
  std::ofstream out("/proc/self/clear_refs");
  out << "5";
}

class BenchReporter : public hos::Reporter {
 public:
  void begin(std::string_view step, std::int64_t) override {
    step_ = std::string(step);
    reset_peak();
    start_ = std::chrono::steady_clock::now();
  }
  void end() override {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const long peak_mb = read_status_kb("VmHWM") / 1024;
    max_peak_mb = std::max(max_peak_mb, peak_mb);
    std::cout << std::left << std::setw(18) << step_ << std::right << std::setw(9) << std::fixed << std::setprecision(2)
              << s << " s  peak RSS " << std::setw(7) << peak_mb << " MB\n";
  }
  void log(hos::LogLevel, std::string_view m) override { std::cout << "  " << m << "\n"; }
  long max_peak_mb = 0;

 private:
  std::string step_;
  std::chrono::steady_clock::time_point start_;
};

// Lat-long sphere with about `faces` faces and a radial bump so faces are
// not all alike.
hos::TriangleMesh bumpy_sphere(int faces) {
  const int rings = std::max(4, static_cast<int>(std::sqrt(faces / 4.0)));
  const int segments = std::max(8, faces / (2 * rings));
  hos::TriangleMesh mesh;
  auto radius = [](double theta, double phi) {
    return 1.0 + 0.0 * std::sin(7 * theta) * std::cos(5 * phi);  // photos show the unit sphere
  };
  for (int i = 0; i <= rings; ++i) {
    const double theta = M_PI * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double phi = 2 * M_PI * j / segments;
      const double r = radius(theta, phi);
      mesh.vertices.emplace_back(r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi),
                                 r * std::cos(theta));
    }
  }
  auto id = [&](int i, int j) { return i * segments + (j % segments); };
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      // Counter-clockwise from outside (theta down from +z, phi around +z).
      mesh.faces.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      mesh.faces.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  }
  return mesh;
}

Eigen::Vector3f albedo(const Eigen::Vector3d& x) {
  const double a = std::sin(40 * x.z() + 9 * x.x()), b = std::cos(33 * x.x() - 21 * x.y());
  return Eigen::Vector3f(0.4f + 0.3f * a, 0.5f + 0.3f * b, 0.45f + 0.25f * a * b);
}

hos::texture::TextureView make_view(int index, int count, int width, int height) {
  const double az = 2 * M_PI * index / count;
  const double el = (index % 3 - 1) * 0.7;
  const Eigen::Vector3d c =
      3.5 * Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  const Eigen::Vector3d f = -c.normalized();
  const Eigen::Vector3d r = f.cross(Eigen::Vector3d::UnitZ()).normalized();
  Eigen::Matrix3d rot;
  rot.row(0) = r;
  rot.row(1) = f.cross(r);
  rot.row(2) = f;
  hos::texture::TextureView view;
  view.name = "view" + std::to_string(index);
  const double focal = 1.2 * width;
  view.camera = hos::Camera::pinhole(1, width, height, focal, focal, width / 2.0, height / 2.0);
  view.pose.cam_from_world_rotation = Eigen::Quaterniond(rot);
  view.pose.cam_from_world_translation = -rot * c;
  view.image = cv::Mat(height, width, CV_8UC3, cv::Scalar(0, 0, 0));
  // Ray cast the unit sphere (the bump is small; the texture only needs plausible photos).
#pragma omp parallel for schedule(dynamic, 16)
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const Eigen::Vector3d d =
          (rot.transpose() * Eigen::Vector3d((x + 0.5 - width / 2.0) / focal, (y + 0.5 - height / 2.0) / focal, 1))
              .normalized();
      const double b = c.dot(d), disc = b * b - (c.squaredNorm() - 1.0);
      if (disc < 0) continue;
      const Eigen::Vector3f a = 255.0f * albedo(c + (-b - std::sqrt(disc)) * d);
      view.image.at<cv::Vec3b>(y, x) =
          cv::Vec3b(cv::saturate_cast<uchar>(a.z()), cv::saturate_cast<uchar>(a.y()), cv::saturate_cast<uchar>(a.x()));
    }
  }
  return view;
}

}  // namespace

int main(int argc, char** argv) {
  int faces = 100000, num_views = 24, width = 1280, height = 960;
  std::string output;
  CLI::App app{"hos-texture-bench: time and peak memory of each texture step"};
  app.add_option("--faces", faces, "approximate face count");
  app.add_option("--views", num_views, "number of photos");
  app.add_option("--width", width, "photo width");
  app.add_option("--height", height, "photo height");
  app.add_option("--output", output, "also write the .glb here (timed)");
  CLI11_PARSE(app, argc, argv);

  const hos::TriangleMesh mesh = bumpy_sphere(faces);
  std::vector<hos::texture::TextureView> views;
  views.reserve(num_views);
  for (int i = 0; i < num_views; ++i) views.push_back(make_view(i, num_views, width, height));
  std::cout << "mesh " << mesh.faces.size() << " faces, " << num_views << " views " << width << "x" << height
            << ", threads " << omp_get_max_threads() << "\n";
  BenchReporter reporter;
  const auto start = std::chrono::steady_clock::now();
  reset_peak();
  const hos::texture::TextureResult result =
      hos::texture::texture_mesh(mesh, views, hos::texture::TextureOptions{}, reporter);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "steps (wall time):\n";
  for (const auto& [step, seconds] : result.stats.step_seconds) {
    std::cout << "  " << std::left << std::setw(16) << step << std::right << std::fixed << std::setprecision(2)
              << std::setw(8) << seconds << " s\n";
  }
  // Resetting the peak counter also resets getrusage's maximum, so the
  // overall peak is the largest step peak.
  std::cout << "texture_mesh total " << total << " s; peak RSS " << reporter.max_peak_mb
            << " MB (includes the scene: mesh and photos)\n";
  std::cout << "charts " << result.stats.num_charts << ", atlases " << result.stats.num_atlases << ", texel scale "
            << result.stats.texel_scale << ", unseen faces " << result.stats.num_unseen_faces << ", seam jump "
            << result.stats.mean_seam_jump_before << " -> " << result.stats.mean_seam_jump_after << "\n";
  if (!output.empty()) {
    const auto t0 = std::chrono::steady_clock::now();
    hos::texture::write_glb(output, result.mesh);
    std::cout << "write_glb " << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s\n";
  }
  return 0;
}
