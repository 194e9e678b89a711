// mvs/depth_map_file.*: what is written is read back bit for bit, and a file
// that is not a whole depth map is named with the reason.
#include "mvs/depth_map_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "tests/support/test_support.h"

namespace hos::mvs {
namespace {

namespace fs = std::filesystem;

DepthMap small_map() {
  DepthMap map{cv::Mat(3, 4, CV_32F), cv::Mat(3, 4, CV_32FC3), cv::Mat(3, 4, CV_32F)};
  cv::randu(map.depth, 1.0, 5.0);
  cv::randu(map.normal, -1.0, 1.0);
  cv::randu(map.cost, 0.0, 2.0);
  map.depth.at<float>(1, 2) = 0.0f;  // no depth
  map.cost.at<float>(1, 2) = kTexturelessCost;
  return map;
}

bool same_bits(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && std::equal(a.datastart, a.dataend, b.datastart, b.dataend);
}

// The error read_depth_map_file throws for file, or "" when it reads it.
std::string read_error(const fs::path& file) {
  return hos::testing::input_error_of([&] { read_depth_map_file(file); });
}

TEST(DepthMapFile, ReadsBackWhatWasWrittenBitForBit) {
  const hos::testing::TempDir dir;
  const DepthMap map = small_map();
  const fs::path file = depth_map_file(dir.path() / "maps", "sub/view.jpg");
  EXPECT_EQ(file, dir.path() / "maps" / "sub/view.jpg.dmap");
  write_depth_map_file(file, map);
  const DepthMap back = read_depth_map_file(file);
  EXPECT_TRUE(same_bits(back.depth, map.depth));
  EXPECT_TRUE(same_bits(back.normal, map.normal));
  EXPECT_TRUE(same_bits(back.cost, map.cost));
}

TEST(DepthMapFile, AFileThatIsNotAWholeDepthMapIsNamedWithTheReason) {
  const hos::testing::TempDir dir;
  const fs::path good = dir / "good.dmap";
  write_depth_map_file(good, small_map());
  std::ifstream in(good, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto write = [&](const std::string& name, const std::string& content) {
    std::ofstream(dir / name, std::ios::binary) << content;
    return dir / name;
  };
  const fs::path other_tag = write("tag.dmap", "HOSDMAP2" + bytes.substr(8));
  const fs::path truncated = write("short.dmap", bytes.substr(0, bytes.size() - 4));
  const fs::path longer = write("long.dmap", bytes + "x");
  // A width of 2^30 pixels: read as it says, it would ask for terabytes.
  std::string huge = bytes;
  const std::int32_t width = 1 << 30;
  huge.replace(8, sizeof(width), reinterpret_cast<const char*>(&width), sizeof(width));
  const fs::path oversized = write("huge.dmap", huge);

  EXPECT_EQ(read_error(good), "");
  for (const fs::path& file : {other_tag, truncated, longer, oversized, dir / "missing.dmap"}) {
    const std::string error = read_error(file);
    EXPECT_NE(error.find(file.filename().string()), std::string::npos) << file << ": " << error;
  }
  EXPECT_NE(read_error(other_tag).find("not a depth map"), std::string::npos);
  EXPECT_NE(read_error(truncated).find("truncated"), std::string::npos);
  EXPECT_NE(read_error(longer).find("damaged"), std::string::npos);
  EXPECT_NE(read_error(oversized).find("damaged"), std::string::npos);
  EXPECT_NE(read_error(dir / "missing.dmap").find("missing"), std::string::npos);
}

}  // namespace
}  // namespace hos::mvs
