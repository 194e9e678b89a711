// hos-sfm --masks with the real COLMAP: photos stored sideways (EXIF
// orientation 6) or upright, downscaled by sfm.max_image_size, each but one
// with a mask over the left quarter of the upright picture, drawn over the
// stored pixels as COLMAP reads them. COLMAP's database must hold no
// keypoint in a masked pixel of the staged photo, where the unmasked photo
// has keypoints; the undistorted workspace carries the masks.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/colmap_io.h"
#include "core/image_mask.h"
#include "core/sparse_model.h"
#include "core/subprocess.h"
#include "tests/sfm/jpeg_fixtures.h"
#include "tests/support/test_support.h"

namespace hos::sfm {
namespace {
namespace fs = std::filesystem;
using hos::testing::read_text;
using hos::testing::shell_quote;

// Keypoint x coordinates per image name, from COLMAP 3.8's database.
std::map<std::string, std::vector<float>> keypoint_xs(const fs::path& file) {
  std::map<std::string, std::vector<float>> out;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(file.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) return out;
  sqlite3_stmt* statement = nullptr;
  const char* sql =
      "SELECT images.name, keypoints.rows, keypoints.cols, keypoints.data FROM keypoints JOIN images ON "
      "keypoints.image_id = images.image_id";
  if (sqlite3_prepare_v2(db, sql, -1, &statement, nullptr) == SQLITE_OK) {
    while (sqlite3_step(statement) == SQLITE_ROW) {
      std::vector<float>& xs = out[reinterpret_cast<const char*>(sqlite3_column_text(statement, 0))];
      const int rows = sqlite3_column_int(statement, 1), cols = sqlite3_column_int(statement, 2);
      const auto* data = static_cast<const float*>(sqlite3_column_blob(statement, 3));
      for (int r = 0; data != nullptr && r < rows; ++r) xs.push_back(data[r * cols]);
    }
  }
  sqlite3_finalize(statement);
  sqlite3_close(db);
  return out;
}

using testing::write_bytes;

TEST(MasksE2e, ColmapExtractsNoFeatureInAMaskedPixel) {
  if (!hos::testing::missing_executables({"hos-sfm", "hos-synth"}).empty()) GTEST_SKIP() << "not built";
  if (find_executable("colmap").empty()) GTEST_SKIP() << "colmap is not installed";
  hos::testing::TempDir dir;
  constexpr int kViews = 12;
  ASSERT_EQ(hos::testing::make_synth_scene(dir / "scene", kViews, 0, dir / "synth.log", {640, 480}), 0)
      << read_text(dir / "synth.log");
  const SparseModel truth = read_colmap_model(dir / "scene" / "sparse");
  fs::create_directories(dir / "photos");
  fs::create_directories(dir / "masks");
  std::string unmasked;
  int index = 0;
  for (const auto& [id, image] : truth.images) {
    const cv::Mat view = cv::imread((dir / "scene" / "images" / image.name).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(view.empty()) << image.name;
    cv::Mat mask(view.size(), CV_8U, cv::Scalar(kUsable));
    mask.colRange(0, view.cols / 4).setTo(kMaskedOut);
    const std::string name = cv::format("IMG_%d.jpg", index);
    testing::PhoneExif exif;
    exif.orientation = index % 2 == 0 ? 6 : 1;
    cv::Mat stored = view, stored_mask = mask;
    if (exif.orientation == 6) {  // stored sideways, turned clockwise when shown
      cv::rotate(view, stored, cv::ROTATE_90_COUNTERCLOCKWISE);
      cv::rotate(mask, stored_mask, cv::ROTATE_90_COUNTERCLOCKWISE);
    }
    write_bytes(dir / "photos" / name, testing::jpeg_with_phone_exif(stored, exif));
    if (index == 1) {
      unmasked = name;
    } else {
      cv::imwrite((dir / "masks" / (name + ".png")).string(), stored_mask);
    }
    ++index;
  }

  const fs::path ws = dir / "ws";
  const int code = hos::testing::run_command(
      shell_quote(hos::testing::executable("hos-sfm").string()) + " --progress plain --images " +
          shell_quote((dir / "photos").string()) + " --workspace " + shell_quote(ws.string()) + " --masks " +
          shell_quote((dir / "masks").string()) + " --set sfm.max_image_size=480",
      dir / "sfm.out");
  ASSERT_EQ(code, 0) << read_text(dir / "sfm.out");
  EXPECT_NE(read_text(dir / "sfm.out").find("masks: 11 of 12 photos have a mask"), std::string::npos)
      << read_text(dir / "sfm.out");

  // Staged 480x360 (upright landscape): the left quarter is x < 120.
  const auto keypoints = keypoint_xs(ws / "sfm" / "database.db");
  ASSERT_EQ(keypoints.size(), static_cast<std::size_t>(kViews));
  for (const auto& [name, xs] : keypoints) {
    SCOPED_TRACE(name);
    ASSERT_GT(xs.size(), 50u);
    const auto in_left_quarter = std::count_if(xs.begin(), xs.end(), [](float x) { return x < 120.0f; });
    if (name == unmasked) {
      EXPECT_GT(in_left_quarter, 20) << "the unmasked photo has features there (the test can fail)";
    } else {
      EXPECT_EQ(in_left_quarter, 0);
    }
  }
  const nlohmann::json report = nlohmann::json::parse(read_text(ws / "sfm" / "report.json"));
  EXPECT_EQ(report.at("masked_photos"), kViews - 1);
  const SparseModel result = read_colmap_model(ws / "sfm" / "undistorted" / "sparse");
  int masks = 0;
  for (const auto& [id, image] : result.images) {
    const fs::path file = mask_file(ws / "sfm" / "undistorted" / "masks", image.name);
    EXPECT_EQ(fs::exists(file), image.name != unmasked) << image.name;
    if (!fs::exists(file)) continue;
    ++masks;
    const Camera& camera = result.camera_of(image);
    const cv::Mat undistorted = read_mask(file, camera.width, camera.height, image.name);
    // Still the left quarter (the undistortion moves pixels by little here).
    EXPECT_EQ(undistorted.at<unsigned char>(camera.height / 2, camera.width / 8), kMaskedOut) << image.name;
    EXPECT_EQ(undistorted.at<unsigned char>(camera.height / 2, camera.width * 2 / 3), kUsable) << image.name;
  }
  EXPECT_EQ(report.at("masks_undistorted"), masks);
  EXPECT_GE(masks, 3);
}

}  // namespace
}  // namespace hos::sfm
