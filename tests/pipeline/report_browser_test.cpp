// Opens a run report from file:// in headless Chromium: the embedded viewer
// must show the model and the console must stay free of errors.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "core/subprocess.h"
#include "pipeline/report.h"
#include "pipeline/report_viewer.h"
#include "pipeline/run_record.h"
#include "pipeline/stage_paths.h"
#include "tests/support/test_support.h"
#include "texture/gltf_writer.h"

namespace hos::pipeline {
namespace {
namespace fs = std::filesystem;

// A square facing +z (the viewer's default view direction) in pure red.
void write_red_square(const fs::path& file) {
  texture::TexturedMesh mesh;
  mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  mesh.normals.assign(4, Eigen::Vector3f(0, 0, 1));
  mesh.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  mesh.indices = {{0, 1, 2, 0, 2, 3}};
  mesh.atlases = {cv::Mat(4, 4, CV_8UC3, cv::Scalar(0, 0, 255))};
  texture::write_glb(file, mesh);
}

// The square fills a good part of the 1000 x 520 viewer; 20000 pixels is
// about 4 % of it, far above anything but the model.
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

TEST(RunReportBrowser, ViewerShowsTheModelWithoutConsoleErrors) {
  const std::string chromium = find_executable("chromium");
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps.sh installs it)";
  const fs::path script = default_viewer_script(hos::testing::bin_dir());
  if (!fs::exists(script)) GTEST_SKIP() << "model-viewer was not fetched at build time (npm missing)";

  hos::testing::TempDir dir;
  const StagePaths paths(dir.path());
  fs::create_directories(paths.textured_model.parent_path());
  write_red_square(paths.textured_model);
  RunRecord record;
  record.stages["texture"].state = "done";
  save_run_record(record, paths.run_record);
  const fs::path page = write_run_report(dir.path(), {script});

  // Headless Chromium takes the screenshot when its virtual time budget is
  // spent, which on a loaded machine can come before the model is decoded:
  // up to three attempts, the model must show in one of them.
  const fs::path shot = dir / "shot.png";
  const fs::path log = dir / "chromium.log";
  int red = 0;
  for (int attempt = 0; attempt < 3 && red <= kMinRedPixels; ++attempt) {
    std::ostringstream command;
    // A headless Chromium that hangs (seen on a loaded machine) ends after
    // 90 s and counts as a failed attempt.
    command << "timeout 90 " << hos::testing::shell_quote(chromium)
            << " --headless --no-sandbox --disable-gpu --enable-unsafe-swiftshader"
               " --disable-background-networking --disable-component-update --disable-sync"
               " --no-first-run --enable-logging=stderr --window-size=1000,900"
               " --virtual-time-budget=20000 --user-data-dir="
            << hos::testing::shell_quote((dir / ("profile" + std::to_string(attempt))).string())
            << " --screenshot=" << hos::testing::shell_quote(shot.string()) << " "
            << hos::testing::shell_quote("file://" + fs::absolute(page).string());
    fs::remove(shot);
    if (hos::testing::run_command(command.str(), log) != 0) continue;
    const cv::Mat image = cv::imread(shot.string(), cv::IMREAD_COLOR);
    if (!image.empty()) red = red_pixels(image);
  }
  EXPECT_GT(red, kMinRedPixels) << hos::testing::read_text(log);
  std::istringstream lines(hos::testing::read_text(log));
  for (std::string line; std::getline(lines, line);) {
    if (line.find("CONSOLE") == std::string::npos) continue;
    EXPECT_EQ(line.find("rror"), std::string::npos) << line;
    EXPECT_EQ(line.find("Uncaught"), std::string::npos) << line;
  }
}

}  // namespace
}  // namespace hos::pipeline
