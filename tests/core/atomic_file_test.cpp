// core/atomic_file.*: a failed write never leaves a finished-looking output.
#include "core/atomic_file.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/support/test_support.h"

namespace hos {
namespace {

TEST(AtomicFile, FailedWriteLeavesNothing) {
  hos::testing::TempDir dir;
  EXPECT_THROW(write_atomically(dir / "out.txt",
                                [](const std::filesystem::path& tmp) {
                                  std::ofstream(tmp) << "half";
                                  throw std::runtime_error("crash");
                                }),
               std::runtime_error);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
  write_atomically(dir / "out.txt", [](const std::filesystem::path& tmp) { std::ofstream(tmp) << "done"; });
  std::ifstream in(dir / "out.txt");
  std::string s;
  in >> s;
  EXPECT_EQ(s, "done");
}

TEST(AtomicFile, FolderIsReplacedOnlyOnSuccess) {
  hos::testing::TempDir dir;
  write_folder_atomically(dir / "ws", [](const std::filesystem::path& tmp) { std::ofstream(tmp / "a") << 1; });
  EXPECT_THROW(write_folder_atomically(dir / "ws",
                                       [](const std::filesystem::path& tmp) {
                                         std::ofstream(tmp / "b") << 2;
                                         throw std::runtime_error("crash");
                                       }),
               std::runtime_error);
  EXPECT_TRUE(std::filesystem::exists(dir / "ws" / "a"));
  EXPECT_FALSE(std::filesystem::exists(dir / "ws" / "b"));
}

}  // namespace
}  // namespace hos
