#include "pipeline/file_hash.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/support/test_support.h"

namespace hos::pipeline {
namespace {
namespace fs = std::filesystem;

std::string contents_hash(const fs::path& p) {
  Fingerprint f;
  f.add_folder_contents(p);
  return f.hex();
}
std::string listing_hash(const fs::path& p) {
  Fingerprint f;
  f.add_folder_listing(p);
  return f.hex();
}

TEST(FileHash, ContentChangesChangeTheFingerprint) {
  hos::testing::TempDir dir;
  std::ofstream(dir / "a.txt") << "hello";
  const std::string h1 = contents_hash(dir.path());
  EXPECT_EQ(contents_hash(dir.path()), h1);
  std::ofstream(dir / "a.txt") << "hellp";
  EXPECT_NE(contents_hash(dir.path()), h1);
  std::ofstream(dir / "b.txt") << "";
  EXPECT_NE(contents_hash(dir.path()), h1);
}

TEST(FileHash, ListingSeesNamesAndSizes) {
  hos::testing::TempDir dir;
  std::ofstream(dir / "a.jpg") << "12345";
  const std::string h1 = listing_hash(dir.path());
  fs::rename(dir / "a.jpg", dir / "b.jpg");
  EXPECT_NE(listing_hash(dir.path()), h1);
  std::ofstream(dir / "b.jpg") << "123456";
  EXPECT_NE(listing_hash(dir.path()), h1);
}

TEST(FileHash, SeparatesParts) {
  Fingerprint a, b;
  a.add("ab");
  a.add("c");
  b.add("a");
  b.add("bc");
  EXPECT_NE(a.hex(), b.hex());
  EXPECT_EQ(a.hex().size(), 16u);
}

}  // namespace
}  // namespace hos::pipeline
