// mvs/run_mvs.*'s split runs (compute_depth_maps on view ranges, then
// fuse_depth_map_folder, under a tight fusion memory budget) against the
// whole run: the same points, byte for byte.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "core/error.h"
#include "core/ply_io.h"
#include "mvs/run_mvs.h"
#include "tests/mvs/synthetic_workspace.h"

namespace hos::mvs {
namespace {

namespace fs = std::filesystem;
using mvs_testing::synthetic_workspace;

std::string file_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Two levels at a small size, so the finer level needs the sources' coarse
// maps (what a split run must recompute) and the test stays quick.
MvsOptions two_levels() {
  MvsOptions o;
  o.coarse_image_size = 160;
  o.max_image_size = 320;
  return o;
}

TEST(SplitMvs, ViewRangesThenFusionEqualTheWholeRunByteForByte) {
  const auto& s = synthetic_workspace();
  const MvsOptions options = two_levels();
  const fs::path root = s.dir->path() / "split_test";
  const MvsResult whole = run_mvs(s.workspace, options, null_reporter(), root / "whole_maps");
  write_point_cloud_ply(root / "whole.ply", whole.points);

  const int views = count_views(s.workspace);
  ASSERT_EQ(views, 12);
  // Three chunks, the last reaching past the last view (a job array's last
  // task gets the rest).
  for (const ViewRange range : {ViewRange{0, 4}, ViewRange{5, 8}, ViewRange{9, 19}}) {
    compute_depth_maps(s.workspace, options, null_reporter(), range, root / "split_maps");
  }
  // Fusion with room for about one view's maps: the others wait in files.
  MvsOptions tight = options;
  tight.fusion_memory_mb = 1;
  const MvsResult split = fuse_depth_map_folder(s.workspace, tight, null_reporter(), root / "split_maps");
  write_point_cloud_ply(root / "split.ply", split.points);

  ASSERT_GT(whole.points.size(), 1000u);
  EXPECT_EQ(split.points.size(), whole.points.size());
  const std::string whole_bytes = file_bytes(root / "whole.ply");
  ASSERT_FALSE(whole_bytes.empty());
  EXPECT_TRUE(file_bytes(root / "split.ply") == whole_bytes) << "split and whole runs' PLYs differ";
  // Every depth map file too (the whole run writes them beside its .tiff maps).
  int maps = 0;
  for (const auto& entry : fs::directory_iterator(root / "whole_maps")) {
    if (entry.path().extension() != ".dmap") continue;
    ++maps;
    EXPECT_TRUE(file_bytes(entry.path()) == file_bytes(root / "split_maps" / entry.path().filename()))
        << entry.path().filename();
  }
  EXPECT_EQ(maps, views - whole.stats.views_skipped);
}

TEST(SplitMvs, RangePastTheLastViewComputesNothing) {
  const auto& s = synthetic_workspace();
  const fs::path folder = s.dir->path() / "split_empty";
  const MvsStats stats = compute_depth_maps(s.workspace, two_levels(), null_reporter(), ViewRange{40, 49}, folder);
  EXPECT_EQ(stats.views, 12);
  EXPECT_TRUE(fs::is_empty(folder));
}

TEST(SplitMvs, FusionNamesAMissingDepthMap) {
  const auto& s = synthetic_workspace();
  const fs::path folder = s.dir->path() / "split_missing";
  compute_depth_maps(s.workspace, two_levels(), null_reporter(), ViewRange{0, 5}, folder);
  try {
    fuse_depth_map_folder(s.workspace, two_levels(), null_reporter(), folder);
    FAIL() << "fusion without the maps of views 6-11 succeeded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(".dmap"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--views"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hos::mvs
