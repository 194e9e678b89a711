
// Opens a run report from file:// in headless Chromium: the embedded viewer
// must show the model from the first registered photo's viewpoint, and the
// console must stay free of errors.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "core/colmap_io.h"
#include "core/ply_io.h"
#include "core/subprocess.h"
#include "pipeline/report/report.h"
#include "pipeline/report/report_viewer.h"
#include "pipeline/run_record.h"
#include "pipeline/stage_paths.h"
#include "tests/support/camera_poses.h"
#include "tests/support/test_support.h"
#include "texture/gltf_writer.h"

namespace hos::pipeline {
namespace {
namespace fs = std::filesystem;

// The glb's root node: rotation, translation and scale, as a placed model's.
Eigen::Matrix4d test_root_matrix() {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = 1.7 * Eigen::AngleAxisd(0.6, Eigen::Vector3d(1, 2, -1).normalized()).toRotationMatrix();
  m.topRightCorner<3, 1>() = Eigen::Vector3d(0.5, 2.0, -1.0);
  return m;
}

// A square of side 2 in the z = 0 plane (SfM frame) in pure red, its
// geometry compressed as `mesh_compression` says.
void write_red_square(const fs::path& file, const std::string& mesh_compression) {
  texture::TexturedMesh mesh;
  mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  mesh.normals.assign(4, Eigen::Vector3f(0, 0, 1));
  mesh.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  mesh.indices = {{0, 1, 2, 0, 2, 3}};
  mesh.atlases = {cv::Mat(4, 4, CV_8UC3, cv::Scalar(0, 0, 255))};
  mesh.root_matrix = test_root_matrix();
  texture::GltfWriteOptions options;
  options.mesh_compression = mesh_compression;
  texture::write_glb(file, mesh, options);
}

// The surface behind the square: a 21 x 21 grid over it and one stray
// triangle 40 units away, which must not move the viewer's centre.
void write_surface(const fs::path& file) {
  TriangleMesh mesh;
  for (int y = 0; y <= 20; ++y) {
    for (int x = 0; x <= 20; ++x) mesh.vertices.emplace_back(-1.0f + x / 10.0f, -1.0f + y / 10.0f, 0.0f);
  }
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 20; ++x) {
      const int v = 21 * y + x;
      mesh.faces.emplace_back(v, v + 1, v + 22);
      mesh.faces.emplace_back(v, v + 22, v + 21);
    }
  }
  const int stray = static_cast<int>(mesh.vertices.size());
  mesh.vertices.emplace_back(40.0f, 40.0f, 0.0f);
  mesh.vertices.emplace_back(40.1f, 40.0f, 0.0f);
  mesh.vertices.emplace_back(40.0f, 40.1f, 0.0f);
  mesh.faces.emplace_back(stray, stray + 1, stray + 2);
  write_mesh_ply(file, mesh, PlyFormat::kBinaryLittleEndian);
}

// A camera at `centre` looking at `at`, image y along -up.
ImageRecord looking_at(int id, const std::string& name, const Eigen::Vector3d& centre, const Eigen::Vector3d& at) {
  const Eigen::Matrix3d cam_from_world = hos::testing::cam_from_world_looking(at - centre, Eigen::Vector3d(0, 1, 0));
  ImageRecord image;
  image.id = id;
  image.camera_id = 1;
  image.name = name;
  image.cam_from_world_rotation = Eigen::Quaterniond(cam_from_world);
  image.cam_from_world_translation = -(cam_from_world * centre);
  return image;
}

// Two photos 640 x 480, focal 500: image 1 (the first registered) looks at
// a point off the square's centre, from the side.
SparseModel photos() {
  SparseModel model;
  model.cameras[1] = Camera::pinhole(1, 640, 480, 500.0, 500.0, 320.0, 240.0);
  model.images[1] = looking_at(1, "first.jpg", Eigen::Vector3d(0.8, -0.6, 3.4), Eigen::Vector3d(0.3, 0.2, 0.0));
  model.images[2] = looking_at(2, "second.jpg", Eigen::Vector3d(-2.0, 0.5, 2.5), Eigen::Vector3d(0.0, 0.0, 0.0));
  return model;
}

// The square fills a good part of the viewer; 20000 pixels is about 4 % of
// it, far above anything but the model.
constexpr int kMinRedPixels = 20000;

// Pixels that are clearly red: the model, nothing else on the page is.
int red_pixels(const cv::Mat& bgr) {
  int count = 0;
  for (int y = 0; y < bgr.rows; ++y) {
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3b& p = bgr.at<cv::Vec3b>(y, x);
      if (p[2] > 120 && p[1] < 80 && p[0] < 80) ++count;
    }
  }
  return count;
}

class RunReportBrowser : public ::testing::Test {
 protected:
  // Red pixels of a screenshot of the page (0 when Chromium fails).
  int red_pixels_shown(int attempt) {
    const fs::path shot = dir_ / "shot.png";
    fs::remove(shot);
    if (!run_chromium("--screenshot=" + hos::testing::shell_quote(shot.string()), dir_ / "stdout.txt", attempt)) {
      return 0;
    }
    const cv::Mat image = cv::imread(shot.string(), cv::IMREAD_COLOR);
    return image.empty() ? 0 : red_pixels(image);
  }

  void SetUp() override {
    chromium_ = find_executable("chromium");
    if (chromium_.empty()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps.sh installs it)";
    const fs::path script = default_viewer_script(hos::testing::bin_dir());
    if (!fs::exists(script)) GTEST_SKIP() << "model-viewer was not fetched at build time (npm missing)";
    const StagePaths paths(dir_.path());
    fs::create_directories(paths.textured_model.parent_path());
    fs::create_directories(paths.mesh.parent_path());
    write_red_square(paths.textured_model, "none");
    write_surface(paths.mesh);
    write_colmap_model(photos(), paths.undistorted / "sparse", ColmapFormat::kText);
    RunRecord record;
    record.stages["texture"].state = "done";
    save_run_record(record, paths.run_record);
    page_ = write_run_report(dir_.path(), {script});
  }

  // Headless Chromium takes the screenshot when its virtual time budget is
  // spent, which on a loaded machine can come before the model is decoded: up
  // to three attempts, the model must show in one of them, and the console
  // stays free of errors.
  void expect_red_model_without_console_errors() {
    int red = 0;
    for (int attempt = 0; attempt < 3 && red <= kMinRedPixels; ++attempt) red = red_pixels_shown(attempt);
    EXPECT_GT(red, kMinRedPixels) << hos::testing::read_text(log_);
    std::istringstream lines(hos::testing::read_text(log_));
    for (std::string line; std::getline(lines, line);) {
      if (line.find("CONSOLE") == std::string::npos) continue;
      EXPECT_EQ(line.find("rror"), std::string::npos) << line;
      EXPECT_EQ(line.find("Uncaught"), std::string::npos) << line;
    }
  }

  // Headless Chromium on the page; `output` is "--screenshot=FILE" or
  // "--dump-dom" (the DOM then goes to out). A Chromium that hangs (seen on a
  // loaded machine) ends after 90 s and fails.
  bool run_chromium(const std::string& output, const fs::path& out, int attempt) {
    std::ostringstream command;
    command << "timeout 90 " << hos::testing::shell_quote(chromium_)
            << " --headless --no-sandbox --disable-gpu --enable-unsafe-swiftshader"
               " --disable-background-networking --disable-component-update --disable-sync"
               " --no-first-run --enable-logging=stderr --window-size=1000,900"
               " --virtual-time-budget=20000 --user-data-dir="
            << hos::testing::shell_quote((dir_ / ("profile" + std::to_string(attempt))).string()) << " " << output
            << " " << hos::testing::shell_quote("file://" + fs::absolute(page_).string()) << " > "
            << hos::testing::shell_quote(out.string()) << " 2> " << hos::testing::shell_quote(log_.string());
    return hos::testing::run_command(command.str()) == 0;
  }

  hos::testing::TempDir dir_;
  std::string chromium_;
  fs::path page_;
  fs::path log_ = dir_ / "chromium.log";
};

TEST_F(RunReportBrowser, ViewerShowsTheModelWithoutConsoleErrors) { expect_red_model_without_console_errors(); }

// The preview as hos-texture writes it, its geometry meshopt-compressed:
// three.js refuses it unless the page tells the bundle where its decoder is.
TEST_F(RunReportBrowser, ViewerShowsAMeshoptPreview) {
  const StagePaths paths(dir_.path());
  write_red_square(report_preview_model(paths), "meshopt");
  page_ = write_run_report(dir_.path(), {default_viewer_script(hos::testing::bin_dir())});
  expect_red_model_without_console_errors();
}

// The camera the page records once the viewer has opened (data-initial-camera).
std::optional<nlohmann::json> initial_camera(const std::string& dom) {
  const std::string key = "data-initial-camera=\"";
  const auto begin = dom.find(key);
  if (begin == std::string::npos) return std::nullopt;
  const auto end = dom.find('"', begin + key.size());
  // Unescaped while copied (GCC 12 warns on std::string::replace here).
  std::string text;
  for (std::size_t i = begin + key.size(); i < end; ++i) {
    if (dom.compare(i, 6, "&quot;") == 0) {
      text += '"';
      i += 5;
    } else {
      text += dom[i];
    }
  }
  return nlohmann::json::parse(text);
}

TEST_F(RunReportBrowser, ViewerOpensFromTheFirstPhotosViewpoint) {
  const fs::path dom_file = dir_ / "dom.html";
  std::optional<nlohmann::json> camera;
  // The DOM is dumped when the virtual time budget is spent, which on a
  // loaded machine often comes before the viewer has opened: up to six
  // attempts, one must show the camera.
  for (int attempt = 0; attempt < 6 && !camera; ++attempt) {
    if (run_chromium("--dump-dom", dom_file, attempt)) camera = initial_camera(hos::testing::read_text(dom_file));
  }
  ASSERT_TRUE(camera) << "no data-initial-camera in the page\n" << hos::testing::read_text(log_);

  // Ground truth: photo 1's centre and optical axis through the root matrix,
  // its vertical field of view 2 atan(240 / 500).
  const Eigen::Matrix4d root = test_root_matrix();
  const ImageRecord first = photos().images.at(1);
  const Eigen::Vector3d position = (root * first.center().homogeneous()).hnormalized();
  const Eigen::Vector3d direction = (root.topLeftCorner<3, 3>() * first.viewing_direction()).normalized();
  const double fov_deg = 2.0 * std::atan(240.0 / 500.0) * 180.0 / std::numbers::pi;
  const auto shown = [&](const char* key) {
    const auto& v = (*camera)[key];
    return Eigen::Vector3d(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  };
  // Bounds: the model is 3.4 units (scaled 1.7) across; a thousandth of
  // that, a tenth of a degree.
  EXPECT_LT((shown("position") - position).norm(), 3.4e-3) << shown("position").transpose();
  EXPECT_LT(std::acos(std::min(1.0, shown("direction").normalized().dot(direction))) * 180.0 / std::numbers::pi, 0.1)
      << shown("direction").transpose() << " against " << direction.transpose();
  EXPECT_NEAR((*camera)["fov_deg"].get<double>(), fov_deg, 0.1);
}

// The robust centre ignores the stray triangle: it is the square's centre.
TEST(ReportViewer, StrayPiecesDoNotMoveTheCentre) {
  hos::testing::TempDir temp;
  write_surface(temp / "surface.ply");
  const TriangleMesh mesh = read_mesh_ply(temp / "surface.ply");
  const Eigen::Matrix4d root = test_root_matrix();
  const std::optional<RobustBounds> bounds = robust_bounds(mesh.vertices, root);
  ASSERT_TRUE(bounds);
  EXPECT_LT((bounds->centre - root.topRightCorner<3, 1>()).norm(), 0.05);
  EXPECT_LT(bounds->size, 1.7 * 2.0 * std::sqrt(3.0));
  // The first photo's orbit: its camera on the sphere about a target on
  // its optical axis.
  const std::vector<PhotoView> views = photo_views(photos(), root, *bounds);
  ASSERT_EQ(views.size(), 2u);
  EXPECT_EQ(views[0].name, "first.jpg");
  const PhotoView& v = views[0];
  const Eigen::Vector3d orbit(std::sin(v.phi) * std::sin(v.theta), std::cos(v.phi),
                              std::sin(v.phi) * std::cos(v.theta));
  EXPECT_LT((v.target + v.radius * orbit - v.position).norm(), 1e-9);
  EXPECT_LT((v.target - v.position).normalized().dot(v.direction), 1.0 + 1e-12);
  EXPECT_GT((v.target - v.position).normalized().dot(v.direction), 1.0 - 1e-12);
}

}  // namespace
}  // namespace hos::pipeline
