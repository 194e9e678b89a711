// The figures hos-sfm writes to WS/sfm/report.json and prints.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "core/reporter.h"
#include "sfm/sfm.h"
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
