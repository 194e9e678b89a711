// hos-synth's command line: the flags other stages' tests call, and bad ones.
#include <gtest/gtest.h>

#include "core/undistorted_workspace.h"
#include "tests/support/test_support.h"

namespace hos {
namespace {
namespace fs = std::filesystem;

std::string synth() { return testing::shell_quote((testing::bin_dir() / "hos-synth").string()); }

TEST(HosSynthMainTest, WritesTheDocumentedLayout) {
  testing::TempDir dir;
  const fs::path out = dir / "scene";
  ASSERT_EQ(testing::run_command(synth() + " --output " + testing::shell_quote(out.string()) +
                                     " --views 4 --width 160 --height 120 --seed 2 --scene torus --ground-plane"
                                     " --rings 1 --jpeg --depth --supersampling 1 --holdout 1 --progress none",
                                 dir / "log"),
            0);
  const UndistortedWorkspace ws = load_undistorted_workspace(out);
  EXPECT_EQ(ws.model.images.size(), 4u);
  EXPECT_TRUE(fs::exists(out / "images" / "view_000.jpg"));
  EXPECT_TRUE(fs::exists(out / "depth" / "view_003.tiff"));
  EXPECT_TRUE(fs::exists(out / "holdout" / "images" / "view_000.jpg"));
  EXPECT_TRUE(fs::exists(out / "gt_mesh.ply"));
  EXPECT_TRUE(fs::exists(out / "gt_objects.ply"));
  EXPECT_TRUE(fs::exists(out / "scene.json"));
}

TEST(HosSynthMainTest, BadInvocationsFailWithUsageErrors) {
  testing::TempDir dir;
  const std::string out = " --output " + testing::shell_quote((dir / "scene").string());
  EXPECT_EQ(testing::run_command(synth() + " --views 4", dir / "log"), 2);  // no --output
  EXPECT_EQ(testing::run_command(synth() + out + " --scene teapot", dir / "log"), 2);
  EXPECT_EQ(testing::run_command(synth() + out + " --views 1", dir / "log"), 2);
  EXPECT_EQ(testing::run_command(synth() + out + " --views 3 --exposure-gains 1,2", dir / "log"), 2);
  EXPECT_FALSE(fs::exists(dir / "scene"));
}

}  // namespace
}  // namespace hos
