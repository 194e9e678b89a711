// mvs/fusion_store.*: views over the memory budget go to files and come back
// unchanged; the views held for a reference view stay in memory.
#include "mvs/fusion_store.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "core/error.h"
#include "mvs/run_mvs.h"
#include "tests/mvs/synthetic_workspace.h"
#include "tests/support/test_support.h"

namespace hos::mvs {
namespace {

constexpr int kStoreWidth = 40, kStoreHeight = 30;

// A view whose maps and colour are noise drawn from `seed`, so that any
// byte lost or moved on the way to the file and back shows.
FusionView noise_view(int seed) {
  cv::RNG rng(static_cast<std::uint64_t>(seed) + 1);
  FusionView v;
  v.map.depth.create(kStoreHeight, kStoreWidth, CV_32F);
  rng.fill(v.map.depth, cv::RNG::UNIFORM, 1.0, 10.0);
  v.map.normal.create(kStoreHeight, kStoreWidth, CV_16SC2);
  rng.fill(v.map.normal, cv::RNG::UNIFORM, -32767, 32767);
  cv::Mat cost(kStoreHeight, kStoreWidth, CV_32F);
  rng.fill(cost, cv::RNG::UNIFORM, 0.0, 2.0);
  cost.convertTo(v.map.cost, CV_16F);
  v.color.create(kStoreHeight, kStoreWidth, CV_8UC3);
  rng.fill(v.color, cv::RNG::UNIFORM, 0, 256);
  return v;
}

bool same_bytes(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && a.isContinuous() && b.isContinuous() &&
         std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

std::size_t view_bytes() { return static_cast<std::size_t>(kStoreWidth * kStoreHeight * fusion_bytes_per_pixel()); }

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

// TMPDIR set for the scope of a test, restored after it.
class ScopedTmpdir {
 public:
  explicit ScopedTmpdir(const std::string& value) {
    if (const char* old = std::getenv("TMPDIR")) old_ = old;
    ::setenv("TMPDIR", value.c_str(), 1);
  }
  ~ScopedTmpdir() {
    if (old_) {
      ::setenv("TMPDIR", old_->c_str(), 1);
    } else {
      ::unsetenv("TMPDIR");
    }
  }
  ScopedTmpdir(const ScopedTmpdir&) = delete;
  ScopedTmpdir& operator=(const ScopedTmpdir&) = delete;

 private:
  std::optional<std::string> old_;
};

std::string spill_error(FusionViewStore& store) {
  try {
    for (int i = 0; i < 2; ++i) store.add(noise_view(i));
  } catch (const OutputError& e) {
    return e.what();
  }
  return "<no OutputError>";
}

TEST(FusionViewStore, AMissingTmpdirMattersOnlyWhenSomethingSpills) {
  const hos::testing::TempDir parent;
  const auto missing = parent.path() / "gone";
  const ScopedTmpdir tmpdir(missing.string());
  FusionViewStore fits(2 * view_bytes());
  for (int i = 0; i < 2; ++i) fits.add(noise_view(i));
  EXPECT_EQ(fits.spilled_views(), 0);

  FusionViewStore spills(view_bytes());
  const std::string message = spill_error(spills);
  EXPECT_NE(message.find("TMPDIR"), std::string::npos) << message;
  EXPECT_NE(message.find(missing.string()), std::string::npos) << message;
  EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;
}

TEST(FusionViewStore, ATmpdirThatIsAFileIsNamed) {
  const hos::testing::TempDir parent;
  const auto file = parent.path() / "a_file";  // unusable even for root
  std::ofstream(file) << "not a folder";
  const ScopedTmpdir tmpdir(file.string());
  FusionViewStore store(view_bytes());
  const std::string message = spill_error(store);
  EXPECT_NE(message.find("TMPDIR"), std::string::npos) << message;
  EXPECT_NE(message.find(file.string()), std::string::npos) << message;
  EXPECT_NE(message.find("Not a directory"), std::string::npos) << message;
}

TEST(FusionViewStore, AReadOnlyTmpdirIsNamed) {
  const hos::testing::TempDir parent;
  const auto read_only = parent.path() / "read_only";
  std::filesystem::create_directory(read_only);
  std::filesystem::permissions(read_only, std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
  if (::access(read_only.c_str(), W_OK) == 0) GTEST_SKIP() << "this user may write to a read-only folder";
  const ScopedTmpdir tmpdir(read_only.string());
  FusionViewStore store(view_bytes());
  const std::string message = spill_error(store);
  EXPECT_NE(message.find("TMPDIR"), std::string::npos) << message;
  EXPECT_NE(message.find("Permission denied"), std::string::npos) << message;
}

// Depth maps that will not fit the budget: an unusable TMPDIR is named
// before the first of them is computed, not after the last.
TEST(FusionViewStore, RunMvsNamesAnUnusableTmpdirBeforeTheDepthMaps) {
  const auto& scene = mvs_testing::synthetic_workspace();  // 12 views of 320x240: 12 MB of maps
  const hos::testing::TempDir dir;
  const auto missing = dir.path() / "gone";
  const ScopedTmpdir tmpdir(missing.string());
  MvsOptions options;
  options.fusion_memory_mb = 1;
  try {
    run_mvs(scene.workspace, options, null_reporter(), dir.path() / "depth_maps");
    FAIL() << "spilling into a TMPDIR that does not exist succeeded";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("TMPDIR"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir.path() / "depth_maps"));
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
