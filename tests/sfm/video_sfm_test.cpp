// hos-sfm on a video clip with the real COLMAP: a hos-synth clip given as
// the photo "folder" registers from the frames hos picks, matched
// sequentially with loop closures, at the accuracy of the true cameras.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "core/colmap_io.h"
#include "core/sparse_model.h"
#include "core/subprocess.h"
#include "tests/support/test_support.h"

namespace hos::sfm {
namespace {
namespace fs = std::filesystem;
using hos::testing::shell_quote;

TEST(SfmVideo, ClipRegistersFromTheChosenFramesSequentially) {
  if (find_executable("colmap").empty()) GTEST_SKIP() << "COLMAP is not installed";
  const std::string missing = hos::testing::missing_executables({"hos-sfm", "hos-synth"});
  if (!missing.empty()) GTEST_SKIP() << "not built:" << missing;
  hos::testing::TempDir dir;
  const fs::path scene = dir / "scene";
  ASSERT_EQ(hos::testing::run_command(shell_quote(hos::testing::executable("hos-synth").string()) + " --output " +
                                          shell_quote(scene.string()) +
                                          " --views 4 --width 320 --height 240 --progress none"
                                          " --video clip.mp4 --video-frames 120",
                                      dir / "synth.log"),
            0);
  // Few frames for exhaustive matching, so the clip is matched sequentially;
  // frames closer than by default, as 320x240 frames hold few features.
  const fs::path ws = dir / "ws";
  ASSERT_EQ(hos::testing::run_command(
                shell_quote(hos::testing::executable("hos-sfm").string()) + " --images " +
                    shell_quote((scene / "video" / "clip.mp4").string()) + " --workspace " + shell_quote(ws.string()) +
                    " --progress plain --set sfm.exhaustive_max_images=10 --set sfm.video_min_motion=0.03",
                dir / "sfm.log"),
            0)
      << hos::testing::read_text(dir / "sfm.log");
  const nlohmann::json report = nlohmann::json::parse(hos::testing::read_text(ws / "sfm" / "report.json"));
  ASSERT_EQ(report["videos"].size(), 1u);
  const nlohmann::json& clip = report["videos"][0];
  EXPECT_EQ(clip["frames"], 120);
  const int kept = clip["kept"];
  EXPECT_GE(kept, 25);
  EXPECT_LE(kept, 60);
  EXPECT_EQ(kept + clip["dropped_too_little_motion"].get<int>() + clip["dropped_blurred"].get<int>(), 120);
  EXPECT_EQ(report["matcher"], "sequential");
  EXPECT_TRUE(report["step_seconds"].contains("vocab_tree_builder"));  // loop closures
  EXPECT_THAT(hos::testing::read_text(dir / "sfm.log"), ::testing::HasSubstr("clip.mp4: kept "));

  // Every kept frame registered, its camera centre where the truth has it.
  const SparseModel truth = read_colmap_model(scene / "video" / "sparse");
  const SparseModel recovered = read_colmap_model(ws / "sfm" / "undistorted" / "sparse");
  ASSERT_EQ(static_cast<int>(recovered.images.size()), kept);
  EXPECT_EQ(recovered.cameras.size(), 1u);
  Eigen::Matrix3Xd from(3, kept), to(3, kept);
  int i = 0;
  for (const auto& [id, image] : recovered.images) {
    const ImageRecord* true_image = truth.find_image(image.name);
    ASSERT_NE(true_image, nullptr) << image.name;
    from.col(i) = image.center();
    to.col(i) = true_image->center();
    ++i;
  }
  const Eigen::Matrix4d similarity = Eigen::umeyama(from, to, true);
  const Eigen::Matrix3Xd mapped =
      (similarity.topLeftCorner<3, 3>() * from).colwise() + similarity.topRightCorner<3, 1>();
  const double extent = (to.rowwise().maxCoeff() - to.rowwise().minCoeff()).norm();
  const double rms = std::sqrt((mapped - to).colwise().squaredNorm().mean());
  EXPECT_LT(rms, 0.01 * extent);
}

}  // namespace
}  // namespace hos::sfm
