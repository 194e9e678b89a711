// core/colmap_io.*: text and binary round trips, and agreement with the real
// COLMAP (its model_converter turns our text into its binary and back).
#include "core/colmap_io.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"
#include "tests/support/sparse_model_fixture.h"
#include "tests/support/test_support.h"

namespace hos {
namespace {

void expect_same(const SparseModel& a, const SparseModel& b) {
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (const auto& [id, c] : a.cameras) {
    const Camera& d = b.cameras.at(id);
    EXPECT_EQ(c.model, d.model);
    EXPECT_EQ(c.width, d.width);
    EXPECT_EQ(c.height, d.height);
    ASSERT_EQ(c.params.size(), d.params.size());
    for (std::size_t k = 0; k < c.params.size(); ++k) EXPECT_NEAR(c.params[k], d.params[k], 1e-9);
  }
  ASSERT_EQ(a.images.size(), b.images.size());
  for (const auto& [id, im] : a.images) {
    const ImageRecord& jm = b.images.at(id);
    EXPECT_EQ(im.name, jm.name);
    EXPECT_EQ(im.camera_id, jm.camera_id);
    EXPECT_LT((im.center() - jm.center()).norm(), 1e-9);
    EXPECT_TRUE(im.cam_from_world_rotation.isApprox(jm.cam_from_world_rotation, 1e-9) ||
                im.cam_from_world_rotation.coeffs().isApprox(-jm.cam_from_world_rotation.coeffs(), 1e-9));
    ASSERT_EQ(im.keypoints.size(), jm.keypoints.size());
    for (std::size_t k = 0; k < im.keypoints.size(); ++k) {
      EXPECT_EQ(im.keypoints[k].point3d_id, jm.keypoints[k].point3d_id);
      EXPECT_LT((im.keypoints[k].xy - jm.keypoints[k].xy).norm(), 1e-9);
    }
  }
  ASSERT_EQ(a.points.size(), b.points.size());
  for (const auto& [id, p] : a.points) {
    const Point3D& q = b.points.at(id);
    EXPECT_LT((p.xyz - q.xyz).norm(), 1e-9);
    EXPECT_EQ(p.color, q.color);
    EXPECT_NEAR(p.error, q.error, 1e-9);
    ASSERT_EQ(p.track.size(), q.track.size());
  }
}

TEST(ColmapIo, TextAndBinaryRoundTrips) {
  hos::testing::TempDir dir;
  const SparseModel model = hos::testing::small_sparse_model();
  write_colmap_model(model, dir / "txt", ColmapFormat::kText);
  write_colmap_model(model, dir / "bin", ColmapFormat::kBinary);
  expect_same(model, read_colmap_model_text(dir / "txt"));
  expect_same(model, read_colmap_model_binary(dir / "bin"));
  expect_same(model, read_colmap_model(dir / "bin"));
  const SparseModelStats stats = compute_stats(model);
  EXPECT_EQ(stats.num_points, 1);
  EXPECT_DOUBLE_EQ(stats.mean_track_length, 2.0);
  EXPECT_DOUBLE_EQ(stats.mean_reprojection_error_px, 0.75);
}

TEST(ColmapIo, AgreesWithTheRealColmap) {
  if (hos::testing::run_command("command -v colmap > /dev/null") != 0) GTEST_SKIP() << "colmap is not installed";
  hos::testing::TempDir dir;
  const SparseModel model = hos::testing::small_sparse_model();
  write_colmap_model(model, dir / "ours_txt", ColmapFormat::kText);
  write_colmap_model(model, dir / "ours_bin", ColmapFormat::kBinary);
  std::filesystem::create_directories(dir / "colmap_bin");
  std::filesystem::create_directories(dir / "colmap_txt");
  const auto convert = [&](const std::string& in, const std::string& out, const std::string& type) {
    return hos::testing::run_command("QT_QPA_PLATFORM=offscreen colmap model_converter --input_path " +
                                         hos::testing::shell_quote((dir / in).string()) + " --output_path " +
                                         hos::testing::shell_quote((dir / out).string()) + " --output_type " + type,
                                     dir / "colmap.log");
  };
  // Our text read by COLMAP, written as COLMAP's binary, read by us.
  ASSERT_EQ(convert("ours_txt", "colmap_bin", "BIN"), 0);
  expect_same(model, read_colmap_model_binary(dir / "colmap_bin"));
  // Our binary read by COLMAP, written as COLMAP's text, read by us.
  ASSERT_EQ(convert("ours_bin", "colmap_txt", "TXT"), 0);
  expect_same(model, read_colmap_model_text(dir / "colmap_txt"));
}

TEST(ColmapIo, MissingOrBrokenFilesNameTheFile) {
  hos::testing::TempDir dir;
  write_colmap_model(hos::testing::small_sparse_model(), dir / "m", ColmapFormat::kBinary);
  std::filesystem::remove(dir / "m" / "points3D.bin");
  try {
    read_colmap_model(dir / "m");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("points3D.bin"), std::string::npos);
  }
  EXPECT_THROW(read_colmap_model(dir / "nothing_here"), InputError);
  // Truncated binary file.
  write_colmap_model(hos::testing::small_sparse_model(), dir / "t", ColmapFormat::kBinary);
  std::filesystem::resize_file(dir / "t" / "images.bin", 30);
  try {
    read_colmap_model(dir / "t");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("images.bin"), std::string::npos);
  }
  // Malformed text line.
  write_colmap_model(hos::testing::small_sparse_model(), dir / "x", ColmapFormat::kText);
  std::ofstream(dir / "x" / "cameras.txt") << "1 PINHOLE 640 480 500 500\n";
  try {
    read_colmap_model(dir / "x");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cameras.txt"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("line 1"), std::string::npos);
  }
}

}  // namespace
}  // namespace hos
