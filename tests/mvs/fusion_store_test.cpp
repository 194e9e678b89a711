// mvs/fusion_store.*: views over the memory budget go to files and come back
// unchanged; the views held for a reference view stay in memory.
#include "mvs/fusion_store.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>

#include "core/error.h"
#include "tests/support/test_support.h"

namespace hos::mvs {
namespace {

constexpr int kWidth = 40, kHeight = 30;

// A view whose maps and colour are noise drawn from `seed`, so that any
// byte lost or moved on the way to the file and back shows.
FusionView noise_view(int seed) {
  cv::RNG rng(static_cast<std::uint64_t>(seed) + 1);
  FusionView v;
  v.map.depth.create(kHeight, kWidth, CV_32F);
  rng.fill(v.map.depth, cv::RNG::UNIFORM, 1.0, 10.0);
  v.map.normal.create(kHeight, kWidth, CV_16SC2);
  rng.fill(v.map.normal, cv::RNG::UNIFORM, -32767, 32767);
  cv::Mat cost(kHeight, kWidth, CV_32F);
  rng.fill(cost, cv::RNG::UNIFORM, 0.0, 2.0);
  cost.convertTo(v.map.cost, CV_16F);
  v.color.create(kHeight, kWidth, CV_8UC3);
  rng.fill(v.color, cv::RNG::UNIFORM, 0, 256);
  return v;
}

bool same_bytes(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && a.isContinuous() && b.isContinuous() &&
         std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

std::size_t view_bytes() { return static_cast<std::size_t>(kWidth * kHeight * fusion_bytes_per_pixel()); }

TEST(FusionViewStore, SpilledMapsComeBackBitForBitAndTheirFolderGoes) {
  const hos::testing::TempDir parent;
  {
    FusionViewStore store(2 * view_bytes(), parent.path());
    for (int i = 0; i < 5; ++i) store.add(noise_view(i));
    EXPECT_EQ(store.spilled_views(), 3);  // the three oldest
    EXPECT_LE(store.peak_resident_bytes(), 2 * view_bytes());
    EXPECT_TRUE(store[0].map.depth.empty());
    EXPECT_FALSE(std::filesystem::is_empty(parent.path()));

    store.hold({0, 1});
    EXPECT_EQ(store.maps_read_back(), 2);
    EXPECT_LE(store.peak_resident_bytes(), 2 * view_bytes());
    for (std::size_t i : {0, 1}) {
      const FusionView expected = noise_view(static_cast<int>(i));
      EXPECT_TRUE(same_bytes(store[i].map.depth, expected.map.depth)) << i;
      EXPECT_TRUE(same_bytes(store[i].map.normal, expected.map.normal)) << i;
      EXPECT_TRUE(same_bytes(store[i].map.cost, expected.map.cost)) << i;
      EXPECT_TRUE(same_bytes(store[i].color, expected.color)) << i;
    }
    // Views 3 and 4 made room; view 3 spilled once, then is read back.
    store.hold({3});
    EXPECT_EQ(store.spilled_views(), 5);
    EXPECT_TRUE(same_bytes(store[3].map.depth, noise_view(3).map.depth));
  }
  EXPECT_TRUE(std::filesystem::is_empty(parent.path()));
}

TEST(FusionViewStore, HeldViewsStayInMemoryBeyondTheBudget) {
  const hos::testing::TempDir parent;
  FusionViewStore store(view_bytes(), parent.path());
  for (int i = 0; i < 4; ++i) store.add(noise_view(i));
  store.hold({0, 1, 2});
  for (std::size_t i : {0, 1, 2}) EXPECT_FALSE(store[i].map.depth.empty()) << i;
  EXPECT_TRUE(store[3].map.depth.empty());
  EXPECT_EQ(store.peak_resident_bytes(), 3 * view_bytes());
}

TEST(FusionViewStore, WithoutABudgetNothingIsSpilled) {
  const hos::testing::TempDir parent;
  FusionViewStore store(0, parent.path());
  for (int i = 0; i < 6; ++i) store.add(noise_view(i));
  store.hold({0});
  EXPECT_EQ(store.spilled_views(), 0);
  EXPECT_EQ(store.peak_resident_bytes(), 6 * view_bytes());
  EXPECT_TRUE(std::filesystem::is_empty(parent.path()));
}

TEST(FusionViewStore, AMissingSpillFolderIsNamed) {
  const hos::testing::TempDir parent;
  const auto missing = parent.path() / "gone";
  FusionViewStore store(view_bytes(), missing);
  store.add(noise_view(0));
  try {
    store.add(noise_view(1));
    FAIL() << "spilling into a folder that does not exist succeeded";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
}

TEST(FusionViewStore, ALostSpillFileIsNamedWhenReadBack) {
  const hos::testing::TempDir parent;
  FusionViewStore store(view_bytes(), parent.path());
  store.add(noise_view(0));
  store.add(noise_view(1));  // spills view 0
  std::filesystem::path lost;
  for (const auto& folder : std::filesystem::directory_iterator(parent.path())) {
    for (const auto& file : std::filesystem::directory_iterator(folder.path())) lost = file.path();
  }
  ASSERT_FALSE(lost.empty());
  std::filesystem::remove(lost);
  try {
    store.hold({0});
    FAIL() << "reading back a removed spill file succeeded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(lost.string()), std::string::npos) << e.what();
  }
}

// Compact maps and colour: 4 + 4 + 2 + 3 bytes a pixel; used masks: 1.
TEST(FusionViewStore, PeakBytesAreTheMasksAndTheBudgetOrOneNeighbourhood) {
  MvsOptions options;
  options.fusion_max_views = 20;
  options.fusion_memory_mb = 1024;
  const double mp = 1e6, budget = 1024.0 * 1024 * 1024;
  EXPECT_DOUBLE_EQ(fusion_peak_bytes(options, mp, 100), 100 * mp + budget);
  EXPECT_DOUBLE_EQ(fusion_peak_bytes(options, mp, 10), 10 * mp + 10 * 13 * mp);  // all fit
  options.fusion_memory_mb = 100;  // a view and its 20 neighbours exceed it
  EXPECT_DOUBLE_EQ(fusion_peak_bytes(options, mp, 50), 50 * mp + 21 * 13 * mp);
  options.fusion_memory_mb = 0;  // no limit
  EXPECT_DOUBLE_EQ(fusion_peak_bytes(options, mp, 50), 50 * mp + 50 * 13 * mp);
}

}  // namespace
}  // namespace hos::mvs
