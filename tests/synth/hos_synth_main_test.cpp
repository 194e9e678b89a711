// hos-synth's command line: the flags other stages' tests call, and bad ones.
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "core/undistorted_workspace.h"
#include "synth/dataset.h"
#include "tests/support/test_support.h"

namespace hos::synth {
namespace {
namespace fs = std::filesystem;

std::string synth() { return hos::testing::shell_quote((hos::testing::bin_dir() / "hos-synth").string()); }

TEST(HosSynthMainTest, WritesTheDocumentedLayout) {
  hos::testing::TempDir dir;
  const fs::path out = dir / "scene";
  ASSERT_EQ(
      hos::testing::run_command(synth() + " --output " + hos::testing::shell_quote(out.string()) +
                                    " --views 4 --width 160 --height 120 --seed 2 --scene torus --ground-plane"
                                    " --rings 1 --jpeg --depth --normals --supersampling 1 --holdout 1 --progress none",
                                dir / "log"),
      0);
  const UndistortedWorkspace ws = load_undistorted_workspace(out);
  EXPECT_EQ(ws.model.images.size(), 4u);
  EXPECT_TRUE(fs::exists(out / "images" / "view_000.jpg"));
  EXPECT_TRUE(fs::exists(out / "depth" / "view_003.tiff"));
  EXPECT_TRUE(fs::exists(out / "holdout" / "images" / "view_000.jpg"));
  const cv::Mat depth = cv::imread((out / "depth" / "view_001.tiff").string(), cv::IMREAD_UNCHANGED);
  const cv::Mat normals =
      decode_normal_map(cv::imread((out / "normals" / "view_001.png").string(), cv::IMREAD_UNCHANGED));
  ASSERT_EQ(depth.type(), CV_32F);
  ASSERT_EQ(normals.type(), CV_32FC3);
  int covered = 0;
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x) {
      const double n = cv::norm(normals.at<cv::Vec3f>(y, x));
      if (depth.at<float>(y, x) > 0) {
        ++covered;
        EXPECT_NEAR(n, 1.0, 1e-3);
      } else {
        EXPECT_EQ(n, 0.0);
      }
    }
  EXPECT_GT(covered, 0);
  EXPECT_TRUE(fs::exists(out / "gt_mesh.ply"));
  EXPECT_TRUE(fs::exists(out / "gt_objects.ply"));
  EXPECT_TRUE(fs::exists(out / "scene.json"));
}

TEST(HosSynthMainTest, BadInvocationsFailWithUsageErrors) {
  hos::testing::TempDir dir;
  const std::string out = " --output " + hos::testing::shell_quote((dir / "scene").string());
  EXPECT_EQ(hos::testing::run_command(synth() + " --views 4", dir / "log"), 2);  // no --output
  EXPECT_EQ(hos::testing::run_command(synth() + out + " --scene teapot", dir / "log"), 2);
  EXPECT_EQ(hos::testing::run_command(synth() + out + " --views 1", dir / "log"), 2);
  EXPECT_EQ(hos::testing::run_command(synth() + out + " --views 3 --exposure-gains 1,2", dir / "log"), 2);
  EXPECT_FALSE(fs::exists(dir / "scene"));
}

TEST(HosSynthMainTest, RefusesToReplaceAFolderItDidNotWrite) {
  hos::testing::TempDir dir;
  fs::create_directories(dir / "mine");
  { std::ofstream(dir / "mine" / "notes.txt") << "keep me"; }
  const std::string flags = " --views 2 --width 64 --height 48 --points 10 --progress none";
  EXPECT_EQ(hos::testing::run_command(
                synth() + " --output " + hos::testing::shell_quote((dir / "mine").string()) + flags, dir / "log"),
            5);
  EXPECT_TRUE(fs::exists(dir / "mine" / "notes.txt"));
  // An earlier output is replaced.
  const std::string out = " --output " + hos::testing::shell_quote((dir / "scene").string());
  ASSERT_EQ(hos::testing::run_command(synth() + out + flags, dir / "log"), 0);
  ASSERT_EQ(hos::testing::run_command(synth() + out + flags + " --jpeg", dir / "log"), 0);
  EXPECT_TRUE(fs::exists(dir / "scene" / "images" / "view_000.jpg"));
  EXPECT_FALSE(fs::exists(dir / "scene" / "images" / "view_000.png"));
}

}  // namespace
}  // namespace hos::synth
