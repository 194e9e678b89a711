// texture/texture_mesh.*'s split runs (compute_view_data on view ranges,
// then texture_mesh_from_view_data) against the whole run: the same .glb,
// byte for byte; a missing or damaged view data file is bad input naming it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "core/error.h"
#include "core/undistorted_workspace.h"
#include "synth/shapes.h"
#include "tests/support/test_support.h"
#include "tests/texture/scene_fixtures.h"
#include "texture/gltf_writer.h"
#include "texture/texture_mesh.h"
#include "texture/view_data.h"

namespace hos::texture {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

std::string file_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class SplitTexture : public ::testing::Test {
 protected:
  void SetUp() override {
    testing::write_sphere_workspace(dir_ / "workspace", kViews);
    workspace_ = load_undistorted_workspace(dir_ / "workspace");
    // Decimated (1280 -> at most 1000 faces), so the parts and the join
    // must decimate alike for their samples to fit.
    options_.max_faces = 1000;
  }
  // Views 0-2, 3-5 and 6-11 (past the last view, as a job array's last task).
  void compute_chunks(const fs::path& folder) {
    for (const ViewRange range : {ViewRange{0, 2}, ViewRange{3, 5}, ViewRange{6, 11}}) {
      compute_view_data(mesh_, workspace_, options_, null_reporter(), range, folder);
    }
  }
  // The view data file of view 4 (view4.png).
  fs::path view4(const fs::path& folder) const { return view_data_file(folder, "view4.png"); }

  static constexpr int kViews = 8;
  hos::testing::TempDir dir_{"hos-split-texture"};
  UndistortedWorkspace workspace_;
  TriangleMesh mesh_ = synth::icosphere(3, 1.0);
  TextureOptions options_;
};

TEST_F(SplitTexture, ViewRangesThenJoinEqualTheWholeRunByteForByte) {
  const TextureResult whole = texture_mesh(mesh_, workspace_, options_, null_reporter());
  write_glb(dir_ / "whole.glb", whole.mesh);
  compute_chunks(dir_ / "view_data");
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir_ / "view_data")) files += entry.path().extension() == ".tvis";
  EXPECT_EQ(files, kViews);
  const TextureResult split =
      texture_mesh_from_view_data(mesh_, workspace_, options_, null_reporter(), dir_ / "view_data");
  write_glb(dir_ / "split.glb", split.mesh);

  ASSERT_LE(whole.stats.faces, 1000u);
  ASSERT_GT(whole.stats.num_candidates, 1000);
  EXPECT_EQ(split.stats.num_candidates, whole.stats.num_candidates);
  const std::string whole_bytes = file_bytes(dir_ / "whole.glb");
  ASSERT_GT(whole_bytes.size(), 1000u);
  EXPECT_TRUE(file_bytes(dir_ / "split.glb") == whole_bytes) << "split and whole runs' .glb files differ";
}

TEST_F(SplitTexture, RangePastTheLastViewComputesNothing) {
  EXPECT_EQ(compute_view_data(mesh_, workspace_, options_, null_reporter(), ViewRange{8, 11}, dir_ / "empty"), 0);
  EXPECT_TRUE(fs::is_empty(dir_ / "empty"));
}

TEST_F(SplitTexture, MissingViewDataIsBadInputNamingTheFile) {
  compute_chunks(dir_ / "view_data");
  fs::remove(view4(dir_ / "view_data"));
  try {
    texture_mesh_from_view_data(mesh_, workspace_, options_, null_reporter(), dir_ / "view_data");
    FAIL() << "the join without view 4's data succeeded";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), view4(dir_ / "view_data").string());
    EXPECT_THAT(e.what(), HasSubstr("--views"));
  }
}

TEST_F(SplitTexture, TruncatedOrForeignViewDataIsBadInputNamingTheFile) {
  compute_chunks(dir_ / "view_data");
  const fs::path file = view4(dir_ / "view_data");
  const std::string bytes = file_bytes(file);
  ASSERT_GT(bytes.size(), 100u);
  const auto expect_refused = [&](const std::string& content, const std::string& reason) {
    std::ofstream(file, std::ios::binary | std::ios::trunc) << content;
    try {
      texture_mesh_from_view_data(mesh_, workspace_, options_, null_reporter(), dir_ / "view_data");
      ADD_FAILURE() << "a view data file that is " << reason << " was accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.path(), file.string()) << reason;
      EXPECT_THAT(e.reason(), HasSubstr(reason));
    }
  };
  expect_refused(bytes.substr(0, bytes.size() - 10), "truncated");
  expect_refused(bytes.substr(0, 20), "truncated");
  expect_refused(bytes + "x", "damaged");
  expect_refused("not a view data file at all", "not a hos-texture view data file");
  expect_refused(file_bytes(view_data_file(dir_ / "view_data", "view3.png")), "does not belong to this run");
  // Another format version: byte 8 holds the version's low byte on this machine.
  std::string other_version = bytes;
  other_version[8] = static_cast<char>(kViewDataVersion + 1);
  expect_refused(other_version, "format version");

  // Data computed with other visibility options belongs to another run.
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  TextureOptions other = options_;
  other.depth_tolerance = 0.02;
  EXPECT_THROW(texture_mesh_from_view_data(mesh_, workspace_, other, null_reporter(), dir_ / "view_data"), InputError);
}

}  // namespace
}  // namespace hos::texture
