// The figures hos-sfm writes to WS/sfm/report.json and prints.
#include "sfm/sfm_report.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "core/reporter.h"
#include "sfm/sfm.h"
#include "tests/support/damaged_file_checks.h"
#include "tests/support/test_support.h"

namespace hos::sfm {
namespace {
using ::testing::HasSubstr;

SfmResult result_with_plan() {
  SfmResult r;
  r.images_given = 11;
  r.images_registered = 11;
  CameraGroup group;
  group.width = 3072;
  group.height = 2304;
  for (int i = 0; i < 11; ++i) group.names.push_back(format_message("p", i, ".jpg"));
  r.plan = plan_sfm({11, 0, 0, {group}}, SfmOptions{});
  r.registered_fraction = 1.0;
  r.matcher = r.plan.matcher;
  r.step_seconds = {{"prepare_images", 0.4},
                    {"feature_extractor", 12.25},
                    {"exhaustive_matcher", 5.0},
                    {"mapper", 8.0},
                    {"image_undistorter", 3.0}};
  r.total_seconds = 28.9;
  return r;
}

TEST(SfmReport, KeepsThePlanAndEveryStepTime) {
  hos::testing::TempDir dir;
  write_sfm_report(result_with_plan(), dir / "report.json");
  std::ifstream in(dir / "report.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["matcher"], "exhaustive");
  EXPECT_EQ(j["plan"]["max_num_features"], 4096);
  ASSERT_EQ(j["plan"]["extractions"].size(), 1u);
  EXPECT_EQ(j["plan"]["extractions"][0]["sift_max_image_size"], 2400);
  EXPECT_EQ(j["plan"]["extractions"][0]["sift_upsample"], false);
  EXPECT_EQ(j["plan"]["extractions"][0]["single_camera"], true);
  EXPECT_EQ(j["plan"]["extractions"][0]["photos"], 11);
  EXPECT_FALSE(j.contains("warning"));
  EXPECT_THAT(j["plan"]["matcher_reason"].get<std::string>(), HasSubstr("11 photos"));
  ASSERT_EQ(j["step_seconds"].size(), 5u);
  EXPECT_DOUBLE_EQ(j["step_seconds"]["feature_extractor"], 12.25);
  EXPECT_DOUBLE_EQ(j["total_seconds"], 28.9);
}

TEST(SfmReport, SummaryNamesTheMatcherAndStepTimes) {
  const auto lines = sfm_summary_lines(result_with_plan());
  std::string text;
  for (const auto& line : lines) text += line + "\n";
  EXPECT_THAT(text, HasSubstr("exhaustive matching (11 photos <= sfm.exhaustive_max_images (30))"));
  EXPECT_THAT(text, HasSubstr("4096 SIFT features per photo"));
  EXPECT_THAT(text, HasSubstr("11 photos 3072x2304: one camera, SIFT at most 2400 px"));
  EXPECT_THAT(text, ::testing::Not(HasSubstr("WARNING")));
  EXPECT_THAT(text, HasSubstr("times: total 28.9 s; prepare_images 0.4 s; feature_extractor 12.2 s;"));
}

TEST(SfmReport, ExistingModelHasNoPlan) {
  hos::testing::TempDir dir;
  SfmResult r;
  r.matcher = "existing model";
  write_sfm_report(r, dir / "report.json");
  std::ifstream in(dir / "report.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_FALSE(j.contains("plan"));
  EXPECT_EQ(j["matcher"], "existing model");
}

TEST(SfmReport, SaysWhereThePrincipalPointWasEstimated) {
  SfmResult r = result_with_plan();
  r.principal_point_estimated = true;
  r.principal_point_offset_px = 23.5;
  r.principal_points = {
      {1, 3072, 2304, 10, true, 23.5, ""},
      {2, 640, 480, 1, false, 0.0, "centre kept: fewer photos than sfm.principal_point_min_images (5)"},
      {3, 640, 480, 2, false, 0.0, "centre kept: fewer photos than sfm.principal_point_min_images (5)"}};
  hos::testing::TempDir dir;
  write_sfm_report(r, dir / "report.json");
  std::ifstream in(dir / "report.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["principal_point"]["estimated"], true);
  EXPECT_DOUBLE_EQ(j["principal_point"]["offset_px"].get<double>(), 23.5);
  ASSERT_EQ(j["principal_point"]["cameras"].size(), 3u);
  EXPECT_EQ(j["principal_point"]["cameras"][1]["estimated"], false);
  EXPECT_EQ(j["principal_point"]["cameras"][1]["images"], 1);
  std::string summary;
  for (const auto& line : sfm_summary_lines(r)) summary += line + "\n";
  EXPECT_THAT(summary, HasSubstr("principal point: camera 1 (3072x2304, 10 photos) 23.5 px off centre; 2 cameras: "
                                 "centre kept: fewer photos than sfm.principal_point_min_images (5)\n"));
}

// 3 of 12 photos registered used to end with exit 0 and only a split
// warning: the summary, the report and the warning now say how much of the
// capture was used and why the rest was not.
TEST(SfmReport, SaysLoudlyHowMuchOfTheCaptureWasUsed) {
  SfmResult r = result_with_plan();
  r.images_given = 12;
  r.images_registered = 3;
  r.registered_fraction = 0.25;
  for (int i = 0; i < 7; ++i) {
    r.unregistered.push_back(format_message("lone", i, ".jpg"));
    r.unregistered_photos.push_back({r.unregistered.back(), i, -1});
  }
  for (int i = 0; i < 2; ++i) {
    r.unregistered.push_back(format_message("other", i, ".jpg"));
    r.unregistered_photos.push_back({r.unregistered.back(), 80, 1});
  }
  r.coverage_warning = coverage_warning_text(r, 15);
  EXPECT_THAT(r.coverage_warning, HasSubstr("only 3 of 12 photos (25%) registered"));
  EXPECT_THAT(r.coverage_warning, HasSubstr("7 matched no other photo well (at most 6 verified matches"));
  EXPECT_THAT(r.coverage_warning, HasSubstr("lone0.jpg"));
  EXPECT_THAT(r.coverage_warning, HasSubstr("2 form separate models"));
  EXPECT_THAT(r.coverage_warning, HasSubstr("overlap"));

  std::string summary;
  for (const auto& line : sfm_summary_lines(r)) summary += line + "\n";
  EXPECT_THAT(summary, HasSubstr("registered 3 of 12 photos (25%)"));
  EXPECT_THAT(summary, HasSubstr("WARNING: only 3 of 12 photos (25%) registered"));
  hos::testing::TempDir dir;
  write_sfm_report(r, dir / "report.json");
  std::ifstream in(dir / "report.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_DOUBLE_EQ(j["registered_fraction"].get<double>(), 0.25);
  EXPECT_EQ(j["warning"], r.coverage_warning);
  ASSERT_EQ(j["unregistered_photos"].size(), 9u);
  EXPECT_EQ(j["unregistered_photos"][3]["best_verified_matches"], 3);
  EXPECT_EQ(j["unregistered_photos"][8]["other_model"], 1);
}

// Every field of the result away from its default: GPS with and without
// altitude, a video clip, a principal point per camera, two models.
SfmResult full_result() {
  SfmResult r = result_with_plan();
  r.images_given = 14;
  r.images_registered = 11;
  r.registered_fraction = 11.0 / 14.0;
  r.coverage_warning = "only 11 of 14 photos (79%) registered";
  r.unregistered = {"x.jpg", "y.jpg"};
  r.unregistered_photos = {{"x.jpg", 4, -1}, {"y.jpg", 90, 1}};
  r.skipped = {{"notes.txt", "not an image"}, {"sub/broken.jpg", "cannot be decoded"}};
  r.photos = {{"p0.jpg", GpsPosition{47.25, 8.5, 412.5}},
              {"p1.jpg", GpsPosition{-33.5, 151.25, std::nullopt}},
              {"p2.jpg", std::nullopt}};
  VideoClipSummary clip;
  clip.file = "clips/walk.mp4";
  clip.name = "walk_mp4";
  clip.selection.frames_read = 300;
  clip.selection.kept = {0, 12, 31};
  clip.selection.too_little_motion = 250;
  clip.selection.blurred = 40;
  clip.selection.over_limit = 7;
  clip.selection.fps = 29.97;
  r.videos = {clip};
  r.masked_photos = 5;
  r.masks_undistorted = 4;
  r.points = 123456;
  r.mean_reprojection_error_px = 0.6875;
  r.mean_track_length = 4.125;
  r.principal_point_estimated = true;
  r.principal_point_offset_px = 23.5;
  r.principal_points = {{1, 3072, 2304, 10, true, 23.5, ""}, {2, 640, 480, 1, false, 0.0, "centre kept"}};
  r.models = {{0, 11, 123456}, {1, 2, 80}};
  r.used_model = 0;
  r.plan.spatial_ignore_z = true;
  r.plan.vocab_tree_words = 768;
  r.cameras_planned = 2;
  r.position_priors = 2;
  r.colmap_version = "COLMAP 3.9.1";
  return r;
}

void expect_equal(const SfmPlanReport& r, const SfmPlanReport& w) {
  EXPECT_EQ(r.matcher, w.matcher);
  EXPECT_EQ(r.matcher_reason, w.matcher_reason);
  EXPECT_EQ(r.spatial_ignore_z, w.spatial_ignore_z);
  EXPECT_EQ(r.max_num_features, w.max_num_features);
  EXPECT_EQ(r.max_num_matches, w.max_num_matches);
  EXPECT_EQ(r.vocab_tree_words, w.vocab_tree_words);
  ASSERT_EQ(r.extractions.size(), w.extractions.size());
  for (std::size_t i = 0; i < w.extractions.size(); ++i) {
    EXPECT_EQ(r.extractions[i].photos, w.extractions[i].photos);
    EXPECT_EQ(r.extractions[i].description, w.extractions[i].description);
    EXPECT_EQ(r.extractions[i].single_camera, w.extractions[i].single_camera);
    EXPECT_EQ(r.extractions[i].sift_max_image_size, w.extractions[i].sift_max_image_size);
    EXPECT_EQ(r.extractions[i].sift_upsample, w.extractions[i].sift_upsample);
  }
}

void expect_equal_lists(const SfmReport& r, const SfmReport& w) {
  EXPECT_EQ(r.unregistered, w.unregistered);
  ASSERT_EQ(r.unregistered_photos.size(), w.unregistered_photos.size());
  for (std::size_t i = 0; i < w.unregistered_photos.size(); ++i) {
    EXPECT_EQ(r.unregistered_photos[i].name, w.unregistered_photos[i].name);
    EXPECT_EQ(r.unregistered_photos[i].best_matches, w.unregistered_photos[i].best_matches);
    EXPECT_EQ(r.unregistered_photos[i].other_model, w.unregistered_photos[i].other_model);
  }
  ASSERT_EQ(r.skipped.size(), w.skipped.size());
  for (std::size_t i = 0; i < w.skipped.size(); ++i) {
    EXPECT_EQ(r.skipped[i].file, w.skipped[i].file);
    EXPECT_EQ(r.skipped[i].reason, w.skipped[i].reason);
  }
  ASSERT_EQ(r.photos.size(), w.photos.size());
  for (std::size_t i = 0; i < w.photos.size(); ++i) {
    EXPECT_EQ(r.photos[i].name, w.photos[i].name);
    ASSERT_EQ(r.photos[i].gps.has_value(), w.photos[i].gps.has_value()) << w.photos[i].name;
    if (!w.photos[i].gps) continue;
    EXPECT_EQ(r.photos[i].gps->latitude_deg, w.photos[i].gps->latitude_deg);
    EXPECT_EQ(r.photos[i].gps->longitude_deg, w.photos[i].gps->longitude_deg);
    EXPECT_EQ(r.photos[i].gps->altitude_m, w.photos[i].gps->altitude_m);
  }
  ASSERT_EQ(r.videos.size(), w.videos.size());
  for (std::size_t i = 0; i < w.videos.size(); ++i) {
    EXPECT_EQ(r.videos[i].file, w.videos[i].file);
    EXPECT_EQ(r.videos[i].name, w.videos[i].name);
    EXPECT_EQ(r.videos[i].frames, w.videos[i].frames);
    EXPECT_EQ(r.videos[i].fps, w.videos[i].fps);
    EXPECT_EQ(r.videos[i].kept_frames, w.videos[i].kept_frames);
    EXPECT_EQ(r.videos[i].dropped_too_little_motion, w.videos[i].dropped_too_little_motion);
    EXPECT_EQ(r.videos[i].dropped_blurred, w.videos[i].dropped_blurred);
    EXPECT_EQ(r.videos[i].dropped_over_max_frames, w.videos[i].dropped_over_max_frames);
  }
  ASSERT_EQ(r.principal_points.size(), w.principal_points.size());
  for (std::size_t i = 0; i < w.principal_points.size(); ++i) {
    const CameraPrincipalPoint &a = r.principal_points[i], &b = w.principal_points[i];
    EXPECT_EQ(a.camera_id, b.camera_id);
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    EXPECT_EQ(a.images, b.images);
    EXPECT_EQ(a.estimated, b.estimated);
    EXPECT_EQ(a.offset_px, b.offset_px);
    EXPECT_EQ(a.reason, b.reason);
  }
  ASSERT_EQ(r.models.size(), w.models.size());
  for (std::size_t i = 0; i < w.models.size(); ++i) {
    EXPECT_EQ(r.models[i].index, w.models[i].index);
    EXPECT_EQ(r.models[i].images, w.models[i].images);
    EXPECT_EQ(r.models[i].points, w.models[i].points);
  }
}

void expect_equal(const SfmReport& r, const SfmReport& w) {
  EXPECT_EQ(r.images_given, w.images_given);
  EXPECT_EQ(r.images_registered, w.images_registered);
  EXPECT_EQ(r.registered_fraction, w.registered_fraction);
  EXPECT_EQ(r.warning, w.warning);
  expect_equal_lists(r, w);
  EXPECT_EQ(r.masked_photos, w.masked_photos);
  EXPECT_EQ(r.masks_undistorted, w.masks_undistorted);
  EXPECT_EQ(r.points, w.points);
  EXPECT_EQ(r.mean_reprojection_error_px, w.mean_reprojection_error_px);
  EXPECT_EQ(r.mean_track_length, w.mean_track_length);
  EXPECT_EQ(r.principal_point_estimated, w.principal_point_estimated);
  EXPECT_EQ(r.principal_point_offset_px, w.principal_point_offset_px);
  EXPECT_EQ(r.used_model, w.used_model);
  EXPECT_EQ(r.matcher, w.matcher);
  ASSERT_EQ(r.plan.has_value(), w.plan.has_value());
  if (w.plan) expect_equal(*r.plan, *w.plan);
  EXPECT_EQ(r.cameras_planned, w.cameras_planned);
  EXPECT_EQ(r.position_priors, w.position_priors);
  EXPECT_EQ(r.colmap_version, w.colmap_version);
  EXPECT_EQ(r.step_seconds, w.step_seconds);
  EXPECT_EQ(r.total_seconds, w.total_seconds);
}

TEST(SfmReport, ReadsBackWhatItWrites) {
  hos::testing::TempDir dir;
  const SfmResult result = full_result();
  write_sfm_report(result, dir / "report.json");
  const SfmReport read = read_sfm_report(dir / "report.json");
  expect_equal(read, sfm_report(result));
  // The result's own figures, as the pipeline sees them.
  EXPECT_EQ(read.images_registered, 11);
  EXPECT_EQ(read.warning, result.coverage_warning);
  ASSERT_EQ(read.videos.size(), 1u);
  EXPECT_EQ(read.videos[0].kept_frames, (std::vector<int>{0, 12, 31}));
  ASSERT_TRUE(read.plan.has_value());
  ASSERT_EQ(read.plan->extractions.size(), 1u);
  EXPECT_EQ(read.plan->extractions[0].photos, 11);
  ASSERT_EQ(read.step_seconds.size(), 5u);
  EXPECT_EQ(read.step_seconds[1], std::make_pair(std::string("feature_extractor"), 12.25));  // in the order they ran
}

// An existing model: no plan, no warning, no videos, priors not checked.
TEST(SfmReport, KeysLeftOutOfTheFileReadAsTheirDefaults) {
  hos::testing::TempDir dir;
  SfmResult result;
  result.matcher = "existing model";
  write_sfm_report(result, dir / "report.json");
  const SfmReport read = read_sfm_report(dir / "report.json");
  expect_equal(read, sfm_report(result));
  EXPECT_FALSE(read.plan.has_value());
  EXPECT_EQ(read.position_priors, -1);
  EXPECT_TRUE(read.warning.empty());
}

TEST(SfmReport, AMissingOrMalformedReportIsAnInputErrorNamingTheFile) {
  hos::testing::expect_input_error_naming_the_file(
      "report.json", [](const std::filesystem::path& file) { read_sfm_report(file); },
      {"", "{\"images_given\": 3", "42", R"({"images_registered": "3"})", R"({"unregistered": "a.jpg"})",
       R"({"skipped": [{"file": 1}]})", R"({"photos": [{"name": "a.jpg", "gps": {"latitude_deg": "N"}}]})",
       R"({"plan": {"extractions": 2}})", R"({"step_seconds": {"mapper": "long"}})",
       R"({"principal_point": {"cameras": [{"width": "wide"}]}})"});
}

// --sparse with a model of other photos used to end in a COLMAP stack
// trace; the sizes are now checked first.
TEST(ModelImageSizes, MismatchNamesThePhotoAndBothSizes) {
  hos::testing::TempDir dir;
  std::filesystem::create_directories(dir / "photos" / "sub");
  cv::imwrite((dir / "photos" / "a.png").string(), cv::Mat(30, 40, CV_8UC3, cv::Scalar(1, 2, 3)));
  cv::imwrite((dir / "photos" / "sub" / "b.png").string(), cv::Mat(60, 80, CV_8UC3, cv::Scalar(1, 2, 3)));
  SparseModel model;
  model.cameras[1] = Camera::pinhole(1, 40, 30, 50, 50, 20, 15);
  model.cameras[2] = Camera::pinhole(2, 80, 60, 50, 50, 40, 30);
  model.images[1].id = 1;
  model.images[1].camera_id = 1;
  model.images[1].name = "a.png";
  model.images[2].id = 2;
  model.images[2].camera_id = 2;
  model.images[2].name = "sub/b.png";
  EXPECT_NO_THROW(check_model_image_sizes(model, dir / "photos"));
  model.cameras[2] = Camera::pinhole(2, 160, 120, 50, 50, 80, 60);
  try {
    check_model_image_sizes(model, dir / "photos");
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), (dir / "photos" / "sub" / "b.png").string());
    EXPECT_THAT(e.reason(), HasSubstr("is 80x60 pixels"));
    EXPECT_THAT(e.reason(), HasSubstr("is 160x120"));
  }
  model.images[3] = model.images[1];
  model.images[3].id = 3;
  model.images[3].name = "missing.png";
  EXPECT_THROW(check_model_image_sizes(model, dir / "photos"), InputError);
}

// The offset of the camera farthest from its centre, relative to its own
// longer side: a 3-4-5 triangle off the centre of each camera.
TEST(PrincipalPointOffset, IsTheLargestOverTheCamerasRelativeToTheLongerSide) {
  SparseModel model;
  Camera wide;
  wide.id = 1;
  wide.model = CameraModel::kPinhole;
  wide.width = 3000;
  wide.height = 2000;
  wide.params = {2500, 2500, 1500 + 30, 1000 - 40};  // 50 px off: 1/60 of 3000
  Camera tall = wide;
  tall.id = 2;
  tall.width = 600;
  tall.height = 1200;
  tall.params = {1000, 1000, 300 - 18, 600 + 24};  // 30 px off: 1/40 of 1200
  model.cameras[1] = wide;
  EXPECT_NEAR(largest_principal_point_offset(model).pixels, 50.0, 1e-9);
  EXPECT_NEAR(largest_principal_point_offset(model).fraction, 50.0 / 3000, 1e-12);
  model.cameras[2] = tall;
  EXPECT_NEAR(largest_principal_point_offset(model).pixels, 30.0, 1e-9);
  EXPECT_NEAR(largest_principal_point_offset(model).fraction, 30.0 / 1200, 1e-12);
}

}  // namespace
}  // namespace hos::sfm
