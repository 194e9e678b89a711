// hos-sfm with the real COLMAP on photos as a phone gives them: in a
// subfolder, half of them stored sideways with an EXIF rotation, two as HEIC,
// GPS without altitude, one with a Latin-1 name. COLMAP must see every photo's
// EXIF focal length (its database's prior_focal_length) and GPS position.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/colmap_io.h"
#include "core/sparse_model.h"
#include "core/subprocess.h"
#include "tests/sfm/jpeg_fixtures.h"
#include "tests/support/test_support.h"

namespace hos::sfm {
namespace {
namespace fs = std::filesystem;
using hos::testing::read_text;
using hos::testing::shell_quote;

using testing::write_bytes;

struct DatabaseCamera {
  double focal_px = 0.0;
  bool focal_prior = false;
};
struct DatabaseImage {
  bool position_prior = false;  // COLMAP stores a missing prior as NULL (NaN)
  double latitude = 0.0;        // COLMAP 3.8: prior_tx, prior_ty = latitude, longitude
  double longitude = 0.0;
};

// The cameras and images tables of a COLMAP 3.8 database.
void read_database(const fs::path& file,
                   std::map<int, DatabaseCamera>& cameras,
                   std::map<std::string, DatabaseImage>& images) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open_v2(file.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK) << file;
  sqlite3_stmt* statement = nullptr;
  ASSERT_EQ(
      sqlite3_prepare_v2(db, "SELECT camera_id, params, prior_focal_length FROM cameras", -1, &statement, nullptr),
      SQLITE_OK);
  while (sqlite3_step(statement) == SQLITE_ROW) {
    DatabaseCamera& camera = cameras[sqlite3_column_int(statement, 0)];
    const auto* params = static_cast<const double*>(sqlite3_column_blob(statement, 1));
    if (params != nullptr && sqlite3_column_bytes(statement, 1) >= 8) camera.focal_px = params[0];
    camera.focal_prior = sqlite3_column_int(statement, 2) != 0;
  }
  sqlite3_finalize(statement);
  ASSERT_EQ(sqlite3_prepare_v2(db, "SELECT name, prior_tx, prior_ty FROM images", -1, &statement, nullptr), SQLITE_OK);
  while (sqlite3_step(statement) == SQLITE_ROW) {
    DatabaseImage& image = images[reinterpret_cast<const char*>(sqlite3_column_text(statement, 0))];
    image.position_prior = sqlite3_column_type(statement, 1) != SQLITE_NULL;
    image.latitude = sqlite3_column_double(statement, 1);
    image.longitude = sqlite3_column_double(statement, 2);
  }
  sqlite3_finalize(statement);
  sqlite3_close(db);
}

TEST(PhotoInputsE2e, PhoneCaptureGivesColmapEveryFocalAndPosition) {
  if (!hos::testing::missing_executables({"hos-sfm", "hos-synth"}).empty()) GTEST_SKIP() << "not built";
  if (find_executable("colmap").empty()) GTEST_SKIP() << "colmap is not installed";
  hos::testing::TempDir dir;
  constexpr int kViews = 12;
  ASSERT_EQ(hos::testing::make_synth_scene(dir / "scene", kViews, 0, dir / "synth.log", {640, 480}), 0)
      << read_text(dir / "synth.log");
  const SparseModel truth = read_colmap_model(dir / "scene" / "sparse");
  const Camera& true_camera = truth.cameras.begin()->second;
  const double true_focal = true_camera.focal_x();

  const fs::path folder = dir / "photos" / "DCIM" / "100APPLE";
  fs::create_directories(folder);
  testing::PhoneExif exif;
  exif.model = "hos phone";
  exif.focal_35mm = static_cast<int>(std::lround(true_focal / 640.0 * 35.0));  // COLMAP: f = f35 / 35 * longest side
  std::map<std::string, std::string> staged_name_of;                           // view -> staged name
  int index = 0;
  for (const auto& [id, image] : truth.images) {
    const cv::Mat view = cv::imread((dir / "scene" / "images" / image.name).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(view.empty()) << image.name;
    exif.latitude_deg = 46.5 + 1e-5 * index;  // no altitude, as many phones
    exif.longitude_deg = 6.6 + 1e-5 * index;
    // Stored sideways, to be turned clockwise (EXIF orientation 6).
    cv::Mat sideways;
    cv::rotate(view, sideways, cv::ROTATE_90_COUNTERCLOCKWISE);
    std::string name;
    if (index == 1 || index == 4) {
      exif.orientation = 6;
      name = "IMG_" + std::to_string(index) + ".HEIC";
      const auto heic = testing::heic_with_exif(sideways, 6, exif);
      if (heic.empty()) GTEST_SKIP() << "libheif has no HEVC encoder here";
      write_bytes(folder / name, heic);
      staged_name_of[image.name] = "DCIM/100APPLE/" + name + ".jpg";
      ++index;
      continue;
    }
    exif.orientation = index % 2 == 0 ? 6 : 1;
    name = index == 3 ? std::string("caf\xE9.jpg") : "IMG_" + std::to_string(index) + ".JPG";
    write_bytes(folder / name, testing::jpeg_with_phone_exif(exif.orientation == 6 ? sideways : view, exif));
    staged_name_of[image.name] = "DCIM/100APPLE/" + name;
    ++index;
  }
  std::ofstream(dir / "photos" / "DCIM" / "100APPLE" / "IMG_2.AAE") << "<?xml version=\"1.0\"?>";

  const fs::path ws = dir / "ws";
  const int code = hos::testing::run_command(
      shell_quote(hos::testing::executable("hos-sfm").string()) + " --progress plain --images " +
          shell_quote((dir / "photos").string()) + " --workspace " + shell_quote(ws.string()),
      dir / "sfm.out");
  ASSERT_EQ(code, 0) << read_text(dir / "sfm.out");

  std::map<int, DatabaseCamera> cameras;
  std::map<std::string, DatabaseImage> images;
  read_database(ws / "sfm" / "database.db", cameras, images);
  ASSERT_EQ(images.size(), static_cast<std::size_t>(kViews));
  for (const auto& [id, camera] : cameras) {
    SCOPED_TRACE(id);
    EXPECT_TRUE(camera.focal_prior) << "COLMAP did not read an EXIF focal length";
    EXPECT_NEAR(camera.focal_px, exif.focal_35mm / 35.0 * 640.0, 1e-6);
  }
  for (const auto& [name, image] : images) {
    SCOPED_TRACE(name);
    EXPECT_TRUE(image.position_prior) << "COLMAP took no GPS position";
  }
  ASSERT_TRUE(images.count(staged_name_of.begin()->second));
  EXPECT_NEAR(images[staged_name_of.begin()->second].latitude, 46.5, 1e-6);

  // Every view registers under its staged name; the report names them all.
  const SparseModel result = read_colmap_model(ws / "sfm" / "undistorted" / "sparse");
  EXPECT_EQ(result.images.size(), truth.images.size());
  for (const auto& [view, staged] : staged_name_of) {
    EXPECT_NE(result.find_image(staged), nullptr) << staged;
    EXPECT_TRUE(fs::exists(ws / "sfm" / "undistorted" / "images" / staged)) << staged;
  }
  const nlohmann::json report = nlohmann::json::parse(read_text(ws / "sfm" / "report.json"));
  EXPECT_EQ(report["images_registered"].get<int>(), kViews);
}

}  // namespace
}  // namespace hos::sfm
