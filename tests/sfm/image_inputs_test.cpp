#include "sfm/image_inputs.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "tests/sfm/jpeg_fixtures.h"
#include "tests/support/test_support.h"

namespace hos::sfm {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

void write_bytes(const fs::path& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

void write_good_jpegs(const fs::path& folder, int count, int width = 120, int height = 90) {
  for (int i = 0; i < count; ++i) {
    cv::imwrite((folder / ("good" + std::to_string(i) + ".jpg")).string(), testing::gradient_image(width, height));
  }
}

// Captures warnings so tests can check that each skipped file is named.
class RecordingReporter : public Reporter {
 public:
  void log(LogLevel level, std::string_view message) override {
    if (level == LogLevel::kWarning) warnings.emplace_back(message);
  }
  std::vector<std::string> warnings;
};

TEST(ImageInputs, MissingFolderIsInputError) {
  hos::testing::TempDir dir;
  try {
    prepare_images(dir / "nope", dir / "staged", SfmOptions{}, null_reporter());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("does not exist"));
  }
}

TEST(ImageInputs, EmptyFolderSaysNoPhotos) {
  hos::testing::TempDir dir;
  fs::create_directories(dir / "photos");
  try {
    prepare_images(dir / "photos", dir / "staged", SfmOptions{}, null_reporter());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("contains no photos"));
  }
}

TEST(ImageInputs, TextFilesAreSkippedByNameThenTooFewIsAnError) {
  hos::testing::TempDir dir;
  fs::create_directories(dir / "photos");
  for (const char* name : {"a.txt", "b.md", "c.jpg"}) {
    std::ofstream(dir / "photos" / name) << "this is not a photo\n";
  }
  RecordingReporter reporter;
  try {
    prepare_images(dir / "photos", dir / "staged", SfmOptions{}, reporter);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("only 0 usable photo"));
    EXPECT_THAT(e.what(), HasSubstr("a.txt"));
    EXPECT_THAT(e.what(), HasSubstr("c.jpg"));
  }
  ASSERT_EQ(reporter.warnings.size(), 3u);
  EXPECT_THAT(reporter.warnings[2], HasSubstr("c.jpg"));
}

TEST(ImageInputs, CorruptZeroByteAndTinyFilesAreSkippedTheRestStaged) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  fs::create_directories(photos);
  write_good_jpegs(photos, 3);
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", testing::gradient_image(200, 150), jpeg);
  jpeg.resize(jpeg.size() / 2);
  write_bytes(photos / "truncated.jpg", jpeg);
  std::vector<std::uint8_t> png;
  cv::imencode(".png", testing::gradient_image(200, 150), png);
  png.resize(png.size() / 2);
  write_bytes(photos / "truncated.png", png);
  write_bytes(photos / "empty.jpg", {});
  cv::imwrite((photos / "tiny.png").string(), testing::gradient_image(20, 20));
  std::ofstream(photos / ".hidden") << "ignored";

  RecordingReporter reporter;
  const ImageInputs inputs = prepare_images(photos, dir / "staged", SfmOptions{}, reporter);
  ASSERT_EQ(inputs.images.size(), 3u);
  EXPECT_EQ(inputs.images[0].name, "good0.jpg");
  EXPECT_TRUE(inputs.same_camera());
  ASSERT_EQ(inputs.skipped.size(), 4u);
  std::map<std::string, std::string> reasons;
  for (const auto& s : inputs.skipped) reasons[s.file.filename().string()] = s.reason;
  EXPECT_THAT(reasons["empty.jpg"], HasSubstr("0 bytes"));
  EXPECT_THAT(reasons["truncated.jpg"], HasSubstr("truncated"));
  EXPECT_THAT(reasons["truncated.png"], HasSubstr("cannot be decoded"));
  EXPECT_THAT(reasons["tiny.png"], HasSubstr("too small"));
  EXPECT_EQ(reporter.warnings.size(), 4u);
  for (int i = 0; i < 3; ++i) {
    const fs::path staged = dir / "staged" / ("good" + std::to_string(i) + ".jpg");
    EXPECT_TRUE(fs::exists(staged)) << staged;
    EXPECT_FALSE(inputs.images[i].rewritten);
  }
  EXPECT_FALSE(fs::exists(dir / "staged" / "truncated.jpg"));
}

TEST(ImageInputs, ExifOrientationIsAppliedAndLargePhotosDownscaled) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  fs::create_directories(photos);
  write_good_jpegs(photos, 2, 200, 100);
  const cv::Mat source = testing::gradient_image(200, 100);
  write_bytes(photos / "portrait.jpg", testing::jpeg_with_exif(source, 6, 24.0, true));
  SfmOptions options;
  options.max_image_size = 150;
  const ImageInputs inputs = prepare_images(photos, dir / "staged", options, null_reporter());
  ASSERT_EQ(inputs.images.size(), 3u);
  const StagedImage& portrait = inputs.images[2];
  ASSERT_EQ(portrait.name, "portrait.jpg");
  EXPECT_TRUE(portrait.rewritten);
  // Orientation 6: turned 90 degrees clockwise, then downscaled to 150 long side.
  EXPECT_EQ(portrait.width, 75);
  EXPECT_EQ(portrait.height, 150);
  EXPECT_FALSE(inputs.same_camera());
  const cv::Mat staged = cv::imread((dir / "staged" / "portrait.jpg").string(), cv::IMREAD_COLOR);
  ASSERT_EQ(staged.cols, 75);
  ASSERT_EQ(staged.rows, 150);
  // After a clockwise turn the source's left column (x = 0, blue channel 0)
  // becomes the top row, and its top row (green 0) the right column.
  EXPECT_LT(staged.at<cv::Vec3b>(2, 37)[0], 30);
  EXPECT_GT(staged.at<cv::Vec3b>(147, 37)[0], 220);
  EXPECT_LT(staged.at<cv::Vec3b>(75, 72)[1], 30);
  EXPECT_GT(staged.at<cv::Vec3b>(75, 2)[1], 220);
  // The originals are untouched.
  EXPECT_EQ(cv::imread((photos / "good0.jpg").string()).cols, 200);
  EXPECT_EQ(inputs.images[0].width, 150);
}

// The run report's thumbnails: one per usable photo, upright, kThumbnailWidth
// wide; none for a skipped file.
TEST(ImageInputs, ThumbnailsAreSmallUprightAndOnlyOfUsablePhotos) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  fs::create_directories(photos);
  write_good_jpegs(photos, 2, 640, 480);
  write_bytes(photos / "portrait.jpg", testing::jpeg_with_exif(testing::gradient_image(640, 480), 6, 24.0, true));
  std::ofstream(photos / "notes.txt") << "not a photo";
  const ImageInputs inputs = prepare_images(photos, dir / "staged", SfmOptions{}, null_reporter(), dir / "thumbs");
  ASSERT_EQ(inputs.images.size(), 3u);
  const cv::Mat landscape = cv::imread((dir / "thumbs" / "good0.jpg.jpg").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(landscape.empty());
  EXPECT_EQ(landscape.cols, kThumbnailWidth);
  EXPECT_EQ(landscape.rows, kThumbnailWidth * 480 / 640);
  const cv::Mat portrait = cv::imread((dir / "thumbs" / "portrait.jpg.jpg").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(portrait.empty());
  EXPECT_EQ(portrait.cols, kThumbnailWidth);
  EXPECT_EQ(portrait.rows, kThumbnailWidth * 640 / 480);
  EXPECT_LT(fs::file_size(dir / "thumbs" / "portrait.jpg.jpg"), 20000u);
  EXPECT_FALSE(fs::exists(dir / "thumbs" / "notes.txt.jpg"));
}

TEST(ImageInputs, OrientationTableMatchesExifDefinition) {
  // A 2x3 image with distinct pixels; each orientation's upright result is
  // checked at its corners against the EXIF definition.
  cv::Mat m(2, 3, CV_8UC1);
  for (int i = 0; i < 6; ++i) m.data[i] = static_cast<std::uint8_t>(i);  // rows: 0 1 2 / 3 4 5
  auto corners = [](const cv::Mat& r) {
    return std::vector<int>{r.at<std::uint8_t>(0, 0), r.at<std::uint8_t>(0, r.cols - 1),
                            r.at<std::uint8_t>(r.rows - 1, 0), r.at<std::uint8_t>(r.rows - 1, r.cols - 1)};
  };
  EXPECT_EQ(corners(apply_exif_orientation(m, 1)), (std::vector<int>{0, 2, 3, 5}));
  EXPECT_EQ(corners(apply_exif_orientation(m, 2)), (std::vector<int>{2, 0, 5, 3}));
  EXPECT_EQ(corners(apply_exif_orientation(m, 3)), (std::vector<int>{5, 3, 2, 0}));
  EXPECT_EQ(corners(apply_exif_orientation(m, 4)), (std::vector<int>{3, 5, 0, 2}));
  EXPECT_EQ(corners(apply_exif_orientation(m, 5)), (std::vector<int>{0, 3, 2, 5}));
  EXPECT_EQ(corners(apply_exif_orientation(m, 6)), (std::vector<int>{3, 0, 5, 2}));
  EXPECT_EQ(corners(apply_exif_orientation(m, 7)), (std::vector<int>{5, 2, 3, 0}));
  EXPECT_EQ(corners(apply_exif_orientation(m, 8)), (std::vector<int>{2, 5, 0, 3}));
}

TEST(ImageInputs, SixteenBitPhotosAreStagedAsEightBits) {
  hos::testing::TempDir dir;
  fs::create_directories(dir / "photos");
  write_good_jpegs(dir / "photos", 2);
  cv::Mat deep;
  testing::gradient_image(120, 90).convertTo(deep, CV_16U, 257.0);  // 8 -> 16 bits, same picture
  ASSERT_TRUE(cv::imwrite((dir / "photos" / "deep.png").string(), deep));
  ASSERT_TRUE(cv::imwrite((dir / "photos" / "deep.tif").string(), deep));
  const ImageInputs inputs = prepare_images(dir / "photos", dir / "staged", SfmOptions{}, null_reporter());
  ASSERT_EQ(inputs.images.size(), 4u);
  for (const char* name : {"deep.png", "deep.tif"}) {
    const cv::Mat staged = cv::imread((dir / "staged" / name).string(), cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(staged.empty()) << name;
    EXPECT_EQ(staged.depth(), CV_8U) << name << " was staged with more than 8 bits (COLMAP cannot read it)";
    // The same picture: within one grey level of the 8-bit original.
    cv::Mat original = testing::gradient_image(120, 90), diff;
    cv::absdiff(staged, original, diff);
    double max_diff = 0.0;
    cv::minMaxLoc(diff.reshape(1), nullptr, &max_diff);
    EXPECT_LE(max_diff, 1.0) << name;
  }
}

TEST(ImageInputs, SymlinkLoopIsSkippedWithAWarning) {
  hos::testing::TempDir dir;
  fs::create_directories(dir / "photos");
  write_good_jpegs(dir / "photos", 3);
  fs::create_symlink("loop.jpg", dir / "photos" / "loop.jpg");  // points at itself
  fs::create_symlink(dir / "photos" / "b_link", dir / "photos" / "a_link");
  fs::create_symlink(dir / "photos" / "a_link", dir / "photos" / "b_link");
  RecordingReporter reporter;
  const ImageInputs inputs = prepare_images(dir / "photos", dir / "staged", SfmOptions{}, reporter);
  EXPECT_EQ(inputs.images.size(), 3u);
  EXPECT_EQ(inputs.skipped.size(), 3u);
  std::string warnings;
  for (const auto& w : reporter.warnings) warnings += w + "\n";
  EXPECT_THAT(warnings, HasSubstr("loop.jpg"));
  EXPECT_THAT(warnings, HasSubstr("a_link"));
}

}  // namespace
}  // namespace hos::sfm
