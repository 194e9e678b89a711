// hos-eval from the command line: JSON output and exit codes.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/exit_codes.h"
#include "core/ply_io.h"
#include "synth/shapes.h"
#include "tests/eval/test_meshes.h"
#include "tests/support/test_support.h"

namespace hos::eval {
namespace {

using hos::testing::read_text;
using hos::testing::shell_quote;

std::string exe() { return shell_quote((hos::testing::bin_dir() / "hos-eval").string()); }

TEST(HosEvalMain, MeshJsonOnStdout) {
  hos::testing::TempDir dir;
  write_mesh_ply(dir / "result.ply", synth::icosphere(4, 1.0));
  write_mesh_ply(dir / "truth.ply", synth::icosphere(4, 1.01));
  const auto out = dir / "out.json";
  ASSERT_EQ(hos::testing::run_command(
                exe() + " mesh --samples 20000 --result " + shell_quote((dir / "result.ply").string()) + " --truth " +
                shell_quote((dir / "truth.ply").string()) + " --json > " + shell_quote(out.string())),
            0)
      << read_text(out);
  const auto j = nlohmann::json::parse(read_text(out));
  EXPECT_NEAR(j["accuracy"]["mean"].get<double>(), 0.01, 5e-4);
  EXPECT_DOUBLE_EQ(j["f_score"].get<double>(), 1.0);
  EXPECT_EQ(j["thresholds"].size(), 3u);
}

TEST(HosEvalMain, SanityJsonFileAndTable) {
  hos::testing::TempDir dir;
  TriangleMesh holed = synth::icosphere(2, 1.0);
  holed.faces.pop_back();
  write_mesh_ply(dir / "m.ply", holed);
  // In a folder that does not exist yet, as WS/eval/ of a pipeline workspace.
  const auto json_path = dir / "eval" / "s.json";
  ASSERT_EQ(hos::testing::run_command(exe() + " sanity --mesh " + shell_quote((dir / "m.ply").string()) + " --json " +
                                          shell_quote(json_path.string()),
                                      dir / "log.txt"),
            0);
  EXPECT_NE(read_text(dir / "log.txt").find("watertight"), std::string::npos);
  const auto j = nlohmann::json::parse(read_text(json_path));
  EXPECT_FALSE(j["watertight"].get<bool>());
  EXPECT_EQ(j["boundary_edges"].get<int>(), 3);
  EXPECT_EQ(j["command"].get<std::string>(), "sanity");
}

TEST(HosEvalMain, BadInputsGiveDocumentedExitCodes) {
  hos::testing::TempDir dir;
  EXPECT_EQ(
      hos::testing::run_command(exe() + " sanity --mesh " + shell_quote((dir / "missing.ply").string()), dir / "a.txt"),
      kExitBadInput);
  EXPECT_NE(read_text(dir / "a.txt").find("missing.ply"), std::string::npos);
  EXPECT_EQ(hos::testing::run_command(exe() + " frobnicate", dir / "b.txt"), kExitUsage);
  write_mesh_ply(dir / "m.ply", synth::icosphere(1, 1.0));
  const std::string m = shell_quote((dir / "m.ply").string());
  EXPECT_EQ(hos::testing::run_command(exe() + " mesh --result " + m + " --truth " + m + " --thresholds 0.01,x",
                                      dir / "c.txt"),
            kExitUsage);
}

// common --region: a rectangle is measured and listed in the JSON; a
// malformed one is a usage error naming it.
TEST(HosEvalMain, CommonMeasuresGivenRegions) {
  hos::testing::TempDir dir;
  // A saved view (render with alpha = mask, beside the photo): the render
  // is off by 20 in the 4x4 block at (8, 8) of a 32x16 grey photo.
  cv::Mat saved(16, 64, CV_8UC4, cv::Scalar(90, 90, 90, 255));
  saved(cv::Rect(8, 8, 4, 4)).setTo(cv::Scalar(110, 110, 110, 255));
  ASSERT_TRUE(cv::imwrite((dir / "a.png").string(), saved));
  const std::string view = shell_quote((dir / "a.png").string());
  const auto out = dir / "out.json";
  ASSERT_EQ(hos::testing::run_command(exe() + " common --saved " + view + " --region 8,8,8,4 --json > " +
                                      shell_quote(out.string())),
            0)
      << read_text(out);
  const auto j = nlohmann::json::parse(read_text(out));
  ASSERT_EQ(j["regions"].size(), 1u);
  EXPECT_EQ(j["regions"][0]["width"].get<int>(), 8);
  EXPECT_EQ(j["regions"][0]["common_pixels"].get<int>(), 32);
  EXPECT_NEAR(j["regions"][0]["mse"][0].get<double>(), 400.0 * 16 / 32, 1e-9);
  EXPECT_NEAR(j["regions"][0]["share"].get<double>(), 1.0, 1e-12);
  EXPECT_EQ(hos::testing::run_command(exe() + " common --saved " + view + " --region 8,8,8", dir / "e.txt"),
            kExitUsage);
  EXPECT_NE(read_text(dir / "e.txt").find("8,8,8"), std::string::npos);
}

}  // namespace
}  // namespace hos::eval
