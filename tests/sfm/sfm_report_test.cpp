// The figures hos-sfm writes to WS/sfm/report.json and prints.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "sfm/sfm.h"
#include "tests/support/test_support.h"

namespace hos::sfm {
namespace {
using ::testing::HasSubstr;

SfmResult result_with_plan() {
  SfmResult r;
  r.images_given = 11;
  r.images_registered = 11;
  r.plan = plan_sfm({11, 0, 3072}, SfmOptions{});
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
  EXPECT_EQ(j["plan"]["sift_max_image_size"], 2400);
  EXPECT_EQ(j["plan"]["sift_upsample"], false);
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
  EXPECT_THAT(text, HasSubstr("4096 SIFT features per photo at most 2400 px"));
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
  hos::testing::TempDir dir;
  write_sfm_report(r, dir / "report.json");
  std::ifstream in(dir / "report.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["principal_point"]["estimated"], true);
  EXPECT_DOUBLE_EQ(j["principal_point"]["offset_px"].get<double>(), 23.5);
  std::string summary;
  for (const auto& line : sfm_summary_lines(r)) summary += line + "\n";
  EXPECT_THAT(summary, HasSubstr("principal point 23.5 px off centre"));
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
