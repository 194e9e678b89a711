// hos-sfm end to end with the real COLMAP: accuracy on a synthetic scene
// with known cameras, and the documented behaviour on bad inputs.
#include "sfm/sfm.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <exiv2/exiv2.hpp>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "core/colmap_io.h"
#include "core/exit_codes.h"
#include "core/reporter.h"
#include "core/sparse_model.h"
#include "core/subprocess.h"
#include "sfm/colmap_database.h"
#include "tests/support/test_support.h"

namespace hos::sfm {
namespace {
namespace fs = std::filesystem;
using hos::testing::read_text;
using hos::testing::shell_quote;
using ::testing::HasSubstr;

bool have_colmap() { return !find_executable("colmap").empty(); }

// Runs hos-sfm; returns the exit code, output in log.
int run_sfm_exe(const std::string& args, const fs::path& log, const std::string& env = "") {
  const std::string command =
      env + " " + shell_quote(hos::testing::executable("hos-sfm").string()) + " --progress plain " + args;
  return hos::testing::run_command(command, log);
}

// Similarity x_gt ~ s R x + t by Umeyama (1991), least squares over pairs.
struct Similarity {
  double scale = 1;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d apply(const Eigen::Vector3d& x) const { return scale * rotation * x + translation; }
};

Similarity umeyama(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to) {
  Eigen::Matrix3Xd a(3, from.size()), b(3, to.size());
  for (std::size_t i = 0; i < from.size(); ++i) {
    a.col(i) = from[i];
    b.col(i) = to[i];
  }
  const Eigen::Matrix4d m = Eigen::umeyama(a, b, true);
  Similarity s;
  s.scale = m.block<3, 3>(0, 0).col(0).norm();
  s.rotation = m.block<3, 3>(0, 0) / s.scale;
  s.translation = m.block<3, 1>(0, 3);
  return s;
}

double rotation_angle_deg(const Eigen::Matrix3d& r) {
  const double c = std::clamp((r.trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c) * 180.0 / M_PI;
}

// Worst camera errors of result against truth after a similarity alignment
// of the centres; the centre error as a fraction of the diagonal of the true
// centres' bounding box. Every true image must be in the result.
struct PoseErrors {
  double worst_centre = 0;
  double worst_rotation_deg = 0;
};

PoseErrors pose_errors(const SparseModel& truth, const SparseModel& result) {
  std::vector<Eigen::Vector3d> estimated, expected;
  Eigen::AlignedBox3d box;
  for (const auto& [id, image] : truth.images) {
    const ImageRecord* match = result.find_image(image.name);
    EXPECT_NE(match, nullptr) << image.name;
    if (!match) return {1e9, 180};
    estimated.push_back(match->center());
    expected.push_back(image.center());
    box.extend(image.center());
  }
  const double scene_size = box.diagonal().norm();
  const Similarity align = umeyama(estimated, expected);
  PoseErrors errors;
  for (const auto& [id, image] : truth.images) {
    const ImageRecord* match = result.find_image(image.name);
    errors.worst_centre =
        std::max(errors.worst_centre, (align.apply(match->center()) - image.center()).norm() / scene_size);
    // cam_from_world of the aligned estimate is R_est * R_align^T.
    const Eigen::Matrix3d aligned = match->rotation() * align.rotation.transpose();
    errors.worst_rotation_deg =
        std::max(errors.worst_rotation_deg, rotation_angle_deg(image.rotation().transpose() * aligned));
  }
  return errors;
}

class SfmTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(hos::testing::executable("hos-sfm"))) GTEST_SKIP() << "hos-sfm is not built";
  }
  // A hos-synth scene (skips the test if hos-synth is not built).
  fs::path synth_scene(int views, hos::testing::SynthPhotoSize size = {}) {
    if (!hos::testing::missing_executables({"hos-synth"}).empty()) return {};
    const fs::path scene = dir_ / "scene";
    const int code = hos::testing::make_synth_scene(scene, views, 0, dir_ / "synth.log", size);
    EXPECT_EQ(code, 0) << read_text(dir_ / "synth.log");
    return code == 0 ? scene : fs::path();
  }
  // count textured images that show unrelated random content.
  fs::path unrelated_images(int count) {
    fs::path folder = dir_ / "unrelated";
    fs::create_directories(folder);
    std::mt19937 rng(7);
    for (int i = 0; i < count; ++i) {
      cv::Mat image(240, 320, CV_8UC3);
      cv::randu(image, cv::Scalar::all(0), cv::Scalar::all(255));
      cv::Mat blurred;
      cv::GaussianBlur(image, blurred, cv::Size(0, 0), 1.5 + i);
      cv::imwrite((folder / ("img" + std::to_string(i) + ".png")).string(), blurred);
    }
    return folder;
  }
  void expect_no_result(const fs::path& ws) {
    EXPECT_FALSE(fs::exists(ws / "sfm" / "undistorted"));
    EXPECT_FALSE(fs::exists(ws / "sfm" / "report.json"));
  }

  hos::testing::TempDir dir_;
};

TEST_F(SfmTest, SyntheticSceneRegistersEveryViewAccurately) {
  if (!have_colmap()) GTEST_SKIP() << "colmap is not installed";
  const fs::path scene = synth_scene(16);
  if (scene.empty()) GTEST_SKIP() << "hos-synth is not built";
  // The photos, cropped by kCrop pixels on the left so the principal point
  // lies kCrop / 2 pixels left of the image centre, plus two bad files that
  // must be skipped with a warning each.
  constexpr int kCrop = 48;
  const fs::path photos = dir_ / "photos";
  fs::create_directories(photos);
  for (const auto& entry : fs::directory_iterator(scene / "images")) {
    const cv::Mat image = cv::imread(entry.path().string());
    cv::imwrite((photos / entry.path().filename()).string(),
                image(cv::Rect(kCrop, 0, image.cols - kCrop, image.rows)).clone());
  }
  std::ofstream(photos / "zero.jpg").close();  // an empty file
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg",
               cv::imread((scene / "images" / fs::directory_iterator(scene / "images")->path().filename()).string()),
               jpeg);
  jpeg.resize(jpeg.size() / 2);
  std::ofstream(photos / "corrupt.jpg", std::ios::binary)
      .write(reinterpret_cast<const char*>(jpeg.data()), jpeg.size());

  const fs::path ws = dir_ / "ws";
  const int code = run_sfm_exe("--images " + shell_quote(photos.string()) + " --workspace " + shell_quote(ws.string()),
                               dir_ / "sfm.out");
  const std::string out = read_text(dir_ / "sfm.out");
  ASSERT_EQ(code, 0) << out;
  EXPECT_THAT(out, HasSubstr("zero.jpg: empty file"));
  EXPECT_THAT(out, HasSubstr("corrupt.jpg: truncated or corrupt JPEG"));
  // COLMAP's own output goes to the log, not the terminal.
  EXPECT_THAT(out, ::testing::Not(HasSubstr("Bundle adjustment report")));
  EXPECT_THAT(read_text(ws / "logs" / "sfm.log"), HasSubstr("Bundle adjustment report"));

  const SparseModel truth = read_colmap_model(scene / "sparse");
  const SparseModel result = read_colmap_model(ws / "sfm" / "undistorted" / "sparse");
  ASSERT_EQ(result.images.size(), truth.images.size()) << "every view registers";
  for (const auto& [id, camera] : result.cameras) EXPECT_FALSE(camera.has_distortion());

  // The final adjustment finds the shifted principal point (the undistorter
  // then resamples the photos around their centre).
  const Camera& true_camera = truth.cameras.begin()->second;
  for (const auto& [id, camera] : read_colmap_model(ws / "sfm" / "sparse" / "principal_point").cameras) {
    const double dx = camera.principal_x() - (true_camera.principal_x() - kCrop);
    const double dy = camera.principal_y() - true_camera.principal_y();
    EXPECT_LT(std::hypot(dx, dy), kCrop / 8.0)
        << "principal point (" << camera.principal_x() << ", " << camera.principal_y() << ")";
  }

  const PoseErrors errors = pose_errors(truth, result);
  EXPECT_LT(errors.worst_centre, 0.01);
  EXPECT_LT(errors.worst_rotation_deg, 1.0);
  std::cout << "worst centre error " << errors.worst_centre * 100 << "% of the scene size, worst rotation error "
            << errors.worst_rotation_deg << " deg\n";

  const std::string report = read_text(ws / "sfm" / "report.json");
  EXPECT_THAT(report, HasSubstr("\"images_registered\": " + std::to_string(truth.images.size())));
  EXPECT_THAT(report, HasSubstr("corrupt.jpg"));
  // The photos support the shifted principal point: it is used.
  EXPECT_TRUE(nlohmann::json::parse(report)["principal_point"]["estimated"].get<bool>()) << report;
}

// Many photos for matcher=auto (a limit of 6): a vocabulary tree learnt from
// the photos; SIFT bounded to half the photo size. The photos are 1280x960:
// at 640x480 the synthetic views keep about 440 features at half size, too
// few to register every view reliably. The cameras must still be
// accurate and full size (keypoints in full-size pixels).
TEST_F(SfmTest, VocabularyTreeAndBoundedSiftKeepFullSizeCameras) {
  if (!have_colmap()) GTEST_SKIP() << "colmap is not installed";
  const fs::path scene = synth_scene(12, {1280, 960});
  if (scene.empty()) GTEST_SKIP() << "hos-synth is not built";
  const fs::path ws = dir_ / "ws";
  const int code =
      run_sfm_exe("--images " + shell_quote((scene / "images").string()) + " --workspace " + shell_quote(ws.string()) +
                      " --set sfm.exhaustive_max_images=6 --set sfm.sift_max_image_size=640",
                  dir_ / "sfm.out");
  const std::string out = read_text(dir_ / "sfm.out");
  ASSERT_EQ(code, 0) << out;
  EXPECT_THAT(out, HasSubstr("vocab_tree matching (12 photos > sfm.exhaustive_max_images (6)"));
  const std::string report = read_text(ws / "sfm" / "report.json");
  EXPECT_THAT(report, HasSubstr("\"sift_max_image_size\": 640"));
  EXPECT_THAT(report, HasSubstr("\"vocab_tree_builder\": "));
  EXPECT_THAT(report, HasSubstr("\"vocab_tree_matcher\": "));

  const SparseModel truth = read_colmap_model(scene / "sparse");
  const SparseModel result = read_colmap_model(ws / "sfm" / "undistorted" / "sparse");
  ASSERT_EQ(result.images.size(), truth.images.size()) << "every view registers";
  const PoseErrors errors = pose_errors(truth, result);
  EXPECT_LT(errors.worst_centre, 0.01);
  EXPECT_LT(errors.worst_rotation_deg, 1.0);
  // Full-size cameras: the true focal length (pixels) within 2%, and images
  // at the photos' size rather than SIFT's 640 px.
  const Camera& true_camera = truth.cameras.begin()->second;
  for (const auto& [id, camera] : result.cameras) {
    EXPECT_NEAR(camera.focal_x(), true_camera.focal_x(), 0.02 * true_camera.focal_x());
    EXPECT_GT(camera.width, 0.9 * true_camera.width);
  }
  const fs::path first = ws / "sfm" / "undistorted" / "images" / result.images.begin()->second.name;
  EXPECT_GT(cv::imread(first.string()).cols, 0.9 * true_camera.width);
}

// The scene's photos copied into folder, each through edit (name, image).
void copy_photos(const fs::path& scene,
                 const fs::path& folder,
                 const std::function<cv::Mat(const std::string&, const cv::Mat&)>& edit) {
  fs::create_directories(folder);
  for (const auto& entry : fs::directory_iterator(scene / "images")) {
    const std::string name = entry.path().filename().string();
    cv::imwrite((folder / name).string(), edit(name, cv::imread(entry.path().string())));
  }
}

// One 1600x1200 photo among 400x300 ones used to turn off SIFT's upsampled
// octave for all of them (6 of 24 registered; 8 of these 16 with the
// upsampling off): each camera group now has its own extraction run and
// SIFT plan.
TEST_F(SfmTest, OneLargePhotoDoesNotDegradeTheSmallOnes) {
  if (!have_colmap()) GTEST_SKIP() << "colmap is not installed";
  const fs::path scene = synth_scene(16, {480, 360});
  if (scene.empty()) GTEST_SKIP() << "hos-synth is not built";
  copy_photos(scene, dir_ / "photos", [](const std::string& name, const cv::Mat& image) {
    cv::Mat out = image;
    if (name == "view_000.png") cv::resize(image, out, cv::Size(1600, 1200), 0, 0, cv::INTER_CUBIC);
    return out;
  });
  const fs::path ws = dir_ / "ws";
  const int code =
      run_sfm_exe("--images " + shell_quote((dir_ / "photos").string()) + " --workspace " + shell_quote(ws.string()),
                  dir_ / "sfm.out");
  const std::string out = read_text(dir_ / "sfm.out");
  ASSERT_EQ(code, 0) << out;
  EXPECT_THAT(out, HasSubstr("15 photos 480x360: one camera, SIFT at most 2400 px (and 2x)"));
  EXPECT_THAT(out, HasSubstr("1 photo 1600x1200: one camera per photo, SIFT at most 2400 px\n"));
  const SparseModel truth = read_colmap_model(scene / "sparse");
  const SparseModel result = read_colmap_model(ws / "sfm" / "undistorted" / "sparse");
  ASSERT_EQ(result.images.size(), truth.images.size()) << "every view registers";
  // The small photos as accurate as without the odd one; the odd one, a
  // blurred upscale with a camera of its own, a little less.
  PoseErrors errors = pose_errors(truth, result);
  EXPECT_LT(errors.worst_centre, 0.01);
  EXPECT_LT(errors.worst_rotation_deg, 2.0);
  SparseModel small_truth = truth;
  std::erase_if(small_truth.images, [](const auto& item) { return item.second.name == "view_000.png"; });
  errors = pose_errors(small_truth, result);
  EXPECT_LT(errors.worst_centre, 0.01);
  EXPECT_LT(errors.worst_rotation_deg, 1.0);
  std::cout << "small photos: worst centre error " << errors.worst_centre * 100
            << "% of the scene size, worst rotation error " << errors.worst_rotation_deg << " deg\n";
}

// Photos of two sizes without EXIF (frames of two videos) used to get one
// camera per photo, and per-photo principal points: now one camera per
// size. Each camera's principal point is estimated from its 8 photos, and
// kept at the centre, where it truly is: the estimate fits the keypoints no
// better than noise would (it was kept 0.3-0.9 px off centre before).
TEST_F(SfmTest, PhotosOfTwoSizesShareOneCameraPerSize) {
  if (!have_colmap()) GTEST_SKIP() << "colmap is not installed";
  const fs::path scene = synth_scene(16, {480, 360});
  if (scene.empty()) GTEST_SKIP() << "hos-synth is not built";
  // Every other view cropped about its centre: the principal point stays at
  // the centre of both sizes.
  int cropped = 0;
  copy_photos(scene, dir_ / "photos", [&](const std::string&, const cv::Mat& image) {
    if (cropped++ % 2) return image;
    return cv::Mat(image(cv::Rect(40, 30, 400, 300)).clone());
  });
  const fs::path ws = dir_ / "ws";
  const int code =
      run_sfm_exe("--images " + shell_quote((dir_ / "photos").string()) + " --workspace " + shell_quote(ws.string()),
                  dir_ / "sfm.out");
  const std::string out = read_text(dir_ / "sfm.out");
  ASSERT_EQ(code, 0) << out;
  const SparseModel truth = read_colmap_model(scene / "sparse");
  const SparseModel mapped = read_colmap_model(ws / "sfm" / "sparse" / "0");
  EXPECT_EQ(mapped.cameras.size(), 2u) << "one camera per size";
  const SparseModel result = read_colmap_model(ws / "sfm" / "undistorted" / "sparse");
  ASSERT_EQ(result.images.size(), truth.images.size()) << "every view registers";
  // COLMAP's multi-threaded runs of this set vary between 0.3 and 1.2
  // degrees of rotation error; per-photo principal points gave 3.9.
  const PoseErrors errors = pose_errors(truth, result);
  EXPECT_LT(errors.worst_centre, 0.01);
  EXPECT_LT(errors.worst_rotation_deg, 2.0);
  std::cout << "worst centre error " << errors.worst_centre * 100 << "% of the scene size, worst rotation error "
            << errors.worst_rotation_deg << " deg\n";
  std::ifstream in(ws / "sfm" / "report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  ASSERT_EQ(report["principal_point"]["cameras"].size(), 2u);
  for (const auto& camera : report["principal_point"]["cameras"]) {
    EXPECT_EQ(camera["images"], 8);
    // The true principal point is the centre of both sizes.
    EXPECT_FALSE(camera["estimated"].get<bool>()) << camera.dump();
    EXPECT_THAT(camera["reason"].get<std::string>(), HasSubstr("no better than noise")) << camera.dump();
  }
  for (const auto& [id, camera] : read_colmap_model(ws / "sfm" / "undistorted" / "sparse").cameras) {
    EXPECT_DOUBLE_EQ(camera.principal_x(), 0.5 * camera.width);
    EXPECT_DOUBLE_EQ(camera.principal_y(), 0.5 * camera.height);
  }
}

// A COLMAP stack trace used to be all the user saw for a model whose
// camera sizes do not match the photos.
TEST_F(SfmTest, ExistingModelOfOtherSizedPhotosIsBadInput) {
  const fs::path scene = synth_scene(4);
  if (scene.empty()) GTEST_SKIP() << "hos-synth is not built";
  copy_photos(scene, dir_ / "photos", [](const std::string&, const cv::Mat& image) {
    cv::Mat half;
    cv::resize(image, half, cv::Size(320, 240), 0, 0, cv::INTER_AREA);
    return half;
  });
  const int code =
      run_sfm_exe("--images " + shell_quote((dir_ / "photos").string()) + " --sparse " +
                      shell_quote((scene / "sparse").string()) + " --workspace " + shell_quote((dir_ / "ws").string()),
                  dir_ / "sfm.out");
  const std::string out = read_text(dir_ / "sfm.out");
  EXPECT_EQ(code, kExitBadInput) << out;
  EXPECT_THAT(out, HasSubstr("view_000.png: is 320x240 pixels but its camera"));
  EXPECT_THAT(out, HasSubstr("is 640x480"));
  EXPECT_THAT(out, ::testing::Not(HasSubstr("Check failed")));
  expect_no_result(dir_ / "ws");
}

// The 16 views of the scene among 6 unrelated images: the run succeeds,
// and says loudly how much of the capture was used and why.
TEST_F(SfmTest, SparseCaptureSaysHowMuchWasUsedAndWhy) {
  if (!have_colmap()) GTEST_SKIP() << "colmap is not installed";
  const fs::path scene = synth_scene(16, {400, 300});
  if (scene.empty()) GTEST_SKIP() << "hos-synth is not built";
  const fs::path photos = unrelated_images(6);
  for (const auto& entry : fs::directory_iterator(scene / "images")) {
    fs::copy_file(entry.path(), photos / entry.path().filename());
  }
  const fs::path ws = dir_ / "ws";
  const int code = run_sfm_exe("--images " + shell_quote(photos.string()) + " --workspace " + shell_quote(ws.string()),
                               dir_ / "sfm.out");
  const std::string out = read_text(dir_ / "sfm.out");
  ASSERT_EQ(code, 0) << out;
  EXPECT_THAT(out, HasSubstr("only 16 of 22 photos (73%) registered"));
  EXPECT_THAT(out, HasSubstr("6 matched no other photo well"));
  EXPECT_THAT(out, HasSubstr("img0.png"));
  EXPECT_THAT(out, HasSubstr("overlap"));
  std::ifstream in(ws / "sfm" / "report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_NEAR(report["registered_fraction"].get<double>(), 16.0 / 22, 1e-9);
  EXPECT_THAT(report["warning"].get<std::string>(), HasSubstr("only 16 of 22 photos"));
}

// "D/1 M/1 S/10000" for EXIF's degrees, minutes, seconds.
std::string exif_dms(double degrees) {
  const int d = static_cast<int>(degrees);
  const int m = static_cast<int>((degrees - d) * 60);
  const long long s = std::llround(((degrees - d) * 60 - m) * 60 * 10000);
  return format_message(d, "/1 ", m, "/1 ", s, "/10000");
}

// Writes an EXIF GPS position without altitude (as many phones do) into a JPEG.
void write_gps_without_altitude(const fs::path& jpeg, double latitude, double longitude) {
  auto image = Exiv2::ImageFactory::open(jpeg.string());
  image->readMetadata();
  Exiv2::ExifData exif;
  exif["Exif.GPSInfo.GPSVersionID"] = "2 3 0 0";
  exif["Exif.GPSInfo.GPSLatitudeRef"] = "N";
  exif["Exif.GPSInfo.GPSLatitude"] = exif_dms(latitude);
  exif["Exif.GPSInfo.GPSLongitudeRef"] = "E";
  exif["Exif.GPSInfo.GPSLongitude"] = exif_dms(longitude);
  image->setExifData(exif);
  image->writeMetadata();
}

// Photos with GPS but no altitude used to reach COLMAP without a position
// (it records one only with an altitude): their priors must now be in the
// database, and spatial matching must ignore height.
TEST_F(SfmTest, GpsWithoutAltitudeReachesColmapAndSpatialMatchingIgnoresHeight) {
  if (!have_colmap()) GTEST_SKIP() << "colmap is not installed";
  const fs::path scene = synth_scene(16, {400, 300});
  if (scene.empty()) GTEST_SKIP() << "hos-synth is not built";
  const fs::path photos = dir_ / "photos";
  fs::create_directories(photos / "DCIM" / "100APPLE");
  int k = 0;
  std::map<std::string, std::pair<double, double>> positions;
  for (const auto& entry : fs::directory_iterator(scene / "images")) {
    // Half of them in a phone's subfolder: names with '/' through the
    // image lists, COLMAP and the undistortion.
    const std::string name = (k % 2 ? "DCIM/100APPLE/" : "") + entry.path().stem().string() + ".jpg";
    cv::imwrite((photos / name).string(), cv::imread(entry.path().string()), {cv::IMWRITE_JPEG_QUALITY, 95});
    // About a metre apart, on a line.
    positions[name] = {46.5 + 1e-5 * k, 6.6 + 1e-5 * k};
    write_gps_without_altitude(photos / name, positions[name].first, positions[name].second);
    ++k;
  }
  const fs::path ws = dir_ / "ws";
  const int code = run_sfm_exe("--images " + shell_quote(photos.string()) + " --workspace " + shell_quote(ws.string()) +
                                   " --set sfm.matcher=spatial",
                               dir_ / "sfm.out");
  const std::string out = read_text(dir_ / "sfm.out");
  ASSERT_EQ(code, 0) << out;
  EXPECT_THAT(out, HasSubstr("16 without altitude: matched by latitude and longitude only"));
  EXPECT_THAT(read_text(ws / "logs" / "sfm.log"), HasSubstr("--SpatialMatching.ignore_z 1"));
  std::ifstream in(ws / "sfm" / "report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_EQ(report["matcher"], "spatial");
  EXPECT_EQ(report["position_priors"], 16);
  EXPECT_EQ(report["plan"]["spatial_ignore_z"], true);
  EXPECT_EQ(report["images_registered"], 16);
  for (const auto& [name, position] : positions) {
    EXPECT_TRUE(fs::exists(ws / "sfm" / "undistorted" / "images" / name)) << name;
  }
  // COLMAP's own record of the positions: latitude, longitude (as COLMAP
  // rounds the seconds: within 0.2 m; neighbours are 1 m apart), altitude 0.
  const auto images = read_database_images(ws / "sfm" / "database.db");
  ASSERT_EQ(images.size(), 16u);
  for (const DatabaseImage& image : images) {
    ASSERT_TRUE(image.position_prior) << image.name;
    EXPECT_NEAR((*image.position_prior)[0], positions.at(image.name).first, 2e-6) << image.name;
    EXPECT_NEAR((*image.position_prior)[1], positions.at(image.name).second, 2e-6) << image.name;
    EXPECT_EQ((*image.position_prior)[2], 0.0) << image.name;
  }
}

TEST_F(SfmTest, ExistingUndistortedModelIsUsedAsIs) {
  const fs::path scene = synth_scene(6);
  if (scene.empty()) GTEST_SKIP() << "hos-synth is not built";
  const fs::path ws = dir_ / "ws";
  // Without COLMAP on PATH: an undistorted model needs none.
  const int code =
      run_sfm_exe("--images " + shell_quote((scene / "images").string()) + " --sparse " +
                      shell_quote((scene / "sparse").string()) + " --workspace " + shell_quote(ws.string()),
                  dir_ / "sfm.out", "env PATH=/nonexistent");
  ASSERT_EQ(code, 0) << read_text(dir_ / "sfm.out");
  const SparseModel truth = read_colmap_model(scene / "sparse");
  const SparseModel copy = read_colmap_model(ws / "sfm" / "undistorted" / "sparse");
  ASSERT_EQ(copy.images.size(), truth.images.size());
  for (const auto& [id, image] : truth.images) {
    const ImageRecord* c = copy.find_image(image.name);
    ASSERT_NE(c, nullptr);
    EXPECT_LT((c->center() - image.center()).norm(), 1e-9);
    EXPECT_TRUE(fs::exists(ws / "sfm" / "undistorted" / "images" / image.name));
  }
}

TEST_F(SfmTest, EmptyFolderIsBadInput) {
  fs::create_directories(dir_ / "empty");
  const int code = run_sfm_exe(
      "--images " + shell_quote((dir_ / "empty").string()) + " --workspace " + shell_quote((dir_ / "ws").string()),
      dir_ / "out");
  EXPECT_EQ(code, kExitBadInput);
  EXPECT_THAT(read_text(dir_ / "out"), HasSubstr("contains no photos"));
  expect_no_result(dir_ / "ws");
}

TEST_F(SfmTest, FolderOfTextFilesIsBadInput) {
  fs::create_directories(dir_ / "text");
  for (const char* name : {"notes.txt", "README.md", "photo.jpg"}) std::ofstream(dir_ / "text" / name) << "text\n";
  const int code = run_sfm_exe(
      "--images " + shell_quote((dir_ / "text").string()) + " --workspace " + shell_quote((dir_ / "ws").string()),
      dir_ / "out");
  EXPECT_EQ(code, kExitBadInput);
  const std::string out = read_text(dir_ / "out");
  EXPECT_THAT(out, HasSubstr("only 0 usable photo"));
  EXPECT_THAT(out, HasSubstr("notes.txt: not a photo"));
  // Recognised by content: a text file named .jpg is not a photo.
  EXPECT_THAT(out, HasSubstr("photo.jpg: not a photo"));
  expect_no_result(dir_ / "ws");
}

TEST_F(SfmTest, NonOverlappingImagesFailCleanly) {
  if (!have_colmap()) GTEST_SKIP() << "colmap is not installed";
  const fs::path photos = unrelated_images(4);
  const int code = run_sfm_exe(
      "--images " + shell_quote(photos.string()) + " --workspace " + shell_quote((dir_ / "ws").string()), dir_ / "out");
  EXPECT_EQ(code, kExitStageFailed);
  const std::string out = read_text(dir_ / "out");
  EXPECT_THAT(out, HasSubstr("overlap"));
  expect_no_result(dir_ / "ws");
}

TEST_F(SfmTest, MissingColmapSaysHowToInstall) {
  const fs::path photos = unrelated_images(3);
  int code =
      run_sfm_exe("--images " + shell_quote(photos.string()) + " --workspace " + shell_quote((dir_ / "ws").string()),
                  dir_ / "out", "env PATH=/nonexistent");
  EXPECT_EQ(code, kExitStageFailed);
  EXPECT_THAT(read_text(dir_ / "out"), HasSubstr("apt-get install colmap"));
  code = run_sfm_exe("--images " + shell_quote(photos.string()) + " --workspace " + shell_quote((dir_ / "ws").string()),
                     dir_ / "out", "env HOS_COLMAP=/no/such/colmap");
  EXPECT_EQ(code, kExitUsage);
  EXPECT_THAT(read_text(dir_ / "out"), HasSubstr("HOS_COLMAP"));
  expect_no_result(dir_ / "ws");
}

TEST_F(SfmTest, UnknownOptionNamesClosestKey) {
  const int code = run_sfm_exe(
      "--images x --workspace " + shell_quote((dir_ / "ws").string()) + " --set sfm.matchr=exhaustive", dir_ / "out");
  EXPECT_EQ(code, kExitUsage);
  EXPECT_THAT(read_text(dir_ / "out"), HasSubstr("did you mean sfm.matcher"));
}

}  // namespace
}  // namespace hos::sfm
