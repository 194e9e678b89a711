#include "sfm/colmap_runner.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>

#include "core/error.h"
#include "tests/support/test_support.h"

namespace hos::sfm {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

TEST(ColmapRunner, ParsesBanner) {
  const ColmapInfo cpu = parse_colmap_banner(
      "COLMAP 3.8 -- Structure-from-Motion and Multi-View Stereo\n"
      "              (Commit Unknown on Unknown without CUDA)\n");
  EXPECT_EQ(cpu.version, "3.8");
  EXPECT_FALSE(cpu.cuda);
  const ColmapInfo gpu = parse_colmap_banner("COLMAP 3.9.1 (Commit 123 on 2023-01-01 with CUDA)");
  EXPECT_EQ(gpu.version, "3.9.1");
  EXPECT_TRUE(gpu.cuda);
  EXPECT_TRUE(parse_colmap_banner("bash: colmap: not found").version.empty());
}

TEST(ColmapRunner, ParsesProgressLines) {
  EXPECT_EQ(parse_colmap_progress("Processed file [7/16]"), 7);
  EXPECT_EQ(parse_colmap_progress("Matching image [3/40] in 1.2s"), 3);
  EXPECT_EQ(parse_colmap_progress("Undistorting image [13/13]"), 13);
  // Block (2, 3) of a 3x4 grid is the 7th block.
  EXPECT_EQ(parse_colmap_progress("Matching block [2/3, 3/4] in 6.982s"), 7);
  EXPECT_EQ(parse_colmap_progress("Registering image #10 (4)"), 4);
  EXPECT_EQ(parse_colmap_progress("Initializing with image pair #11 and #2"), 2);
  EXPECT_FALSE(parse_colmap_progress("  Name:            templeSR0001.png").has_value());
  EXPECT_FALSE(parse_colmap_progress("Bundle adjustment report").has_value());
  EXPECT_FALSE(parse_colmap_progress("").has_value());
}

TEST(ColmapRunner, TailIsIndented) { EXPECT_EQ(format_tail({"a", "b"}), "\n    a\n    b"); }

TEST(ColmapRunner, FullDiskNamesTheDiskAndFolderAsAnOutputError) {
  // A stand-in for COLMAP that fails the way SQLite does on a full disk.
  hos::testing::TempDir dir;
  const fs::path fake = dir / "colmap";
  std::ofstream(fake) << "#!/bin/sh\necho 'E1202 sqlite3.cc: SQLite error: database or disk is full'\nexit 1\n";
  ::chmod(fake.c_str(), 0755);
  ColmapInfo colmap;
  colmap.executable = fake.string();
  const ColmapStep step{"feature_extractor", {"--database_path", (dir / "ws" / "database.db").string()}, "features", 0};
  try {
    run_colmap_step(colmap, step, null_reporter());
    FAIL() << "no error";
  } catch (const OutputError& e) {
    EXPECT_THAT(e.what(), HasSubstr((dir / "ws").string()));
    EXPECT_THAT(e.what(), HasSubstr("the disk is full: the disk mounted at"));
    EXPECT_THAT(e.what(), HasSubstr("database or disk is full"));
  }
}

}  // namespace
}  // namespace hos::sfm
