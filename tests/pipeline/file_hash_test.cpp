#include "pipeline/file_hash.h"

#include <gtest/gtest.h>

#include <fstream>

#include "pipeline/driver.h"
#include "pipeline/stage_paths.h"
#include "pipeline/stages.h"
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

// The sfm stage's fingerprint covers the photos it reads and nothing else:
// a sidecar, a note or .DS_Store next to the photos (or in a subfolder)
// does not re-run COLMAP; a changed or added photo does, in a subfolder too.
TEST(FileHash, SfmFingerprintCoversOnlyThePhotos) {
  hos::testing::TempDir dir;
  fs::create_directories(dir / "photos" / "DCIM");
  const auto jpeg = [](const fs::path& file, const std::string& payload) {
    std::ofstream(file, std::ios::binary) << std::string("\xFF\xD8\xFF\xE0", 4) << payload;
  };
  jpeg(dir / "photos" / "a.jpg", "one");
  jpeg(dir / "photos" / "DCIM" / "b.JPG", "two");
  DriverOptions options;
  options.photos = dir / "photos";
  options.output = dir / "out.glb";
  const StagePaths paths(dir / "ws");
  const PipelineConfig config;
  const auto fingerprint = [&] {
    Fingerprint f;
    pipeline_stages().at(stage_index("sfm", "--from")).inputs(f, options, config, paths);
    return f.hex();
  };
  const std::string before = fingerprint();
  std::ofstream(dir / "photos" / ".DS_Store") << "finder";
  std::ofstream(dir / "photos" / "a.xmp") << "<x:xmpmeta/>";
  std::ofstream(dir / "photos" / "DCIM" / "b.AAE") << "<?xml version=\"1.0\"?>";
  std::ofstream(dir / "photos" / "notes.txt") << "a note";
  EXPECT_EQ(fingerprint(), before);
  jpeg(dir / "photos" / "DCIM" / "b.JPG", "two, edited");
  const std::string edited = fingerprint();
  EXPECT_NE(edited, before);
  jpeg(dir / "photos" / "c.heic.jpg", "three");
  EXPECT_NE(fingerprint(), edited);
}

// The masks in the folder sfm.masks names are inputs of sfm too (those
// beside the photos are among the photo files): a mask edited in place
// re-runs the stage.
TEST(FileHash, SfmFingerprintCoversTheMasks) {
  hos::testing::TempDir dir;
  fs::create_directories(dir / "photos");
  fs::create_directories(dir / "masks");
  std::ofstream(dir / "photos" / "a.jpg", std::ios::binary) << std::string("\xFF\xD8\xFF\xE0", 4) << "photo";
  const auto png = [](const fs::path& file, const std::string& payload) {
    std::ofstream(file, std::ios::binary) << std::string("\x89PNG\r\n\x1A\n", 8) << payload;
  };
  png(dir / "masks" / "a.jpg.png", "mask");
  DriverOptions options;
  options.photos = dir / "photos";
  options.output = dir / "out.glb";
  const StagePaths paths(dir / "ws");
  PipelineConfig config;
  config.apply_assignment("sfm.masks=" + (dir / "masks").string());
  const auto fingerprint = [&] {
    Fingerprint f;
    pipeline_stages().at(stage_index("sfm", "--from")).inputs(f, options, config, paths);
    return f.hex();
  };
  const std::string before = fingerprint();
  png(dir / "masks" / "a.jpg.png", "mask, painted over");
  EXPECT_NE(fingerprint(), before);
}

}  // namespace
}  // namespace hos::pipeline
