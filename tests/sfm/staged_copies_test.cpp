// The copies hos-sfm re-encodes for COLMAP (turned by their EXIF
// orientation, shrunk, decoded from HEIC) keep the photo's colour detail.
#include <gtest/gtest.h>

#include <algorithm>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sfm/image_inputs.h"
#include "sfm/sfm_options.h"
#include "tests/sfm/jpeg_fixtures.h"
#include "tests/support/test_support.h"

namespace hos::sfm {
namespace {
namespace fs = std::filesystem;

TEST(StagedCopies, TurnedAndShrunkJpegsKeepFullChroma) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  fs::create_directories(photos);
  const cv::Mat source = testing::gradient_image(400, 300);
  testing::write_bytes(photos / "a.jpg", testing::jpeg_with_exif(source, 1, 24.0, true));
  testing::write_bytes(photos / "b.jpg", testing::jpeg_with_exif(source, 1, 24.0, true));
  testing::write_bytes(photos / "portrait.jpg", testing::jpeg_with_exif(source, 6, 24.0, true));
  SfmOptions options;
  options.max_image_size = 200;  // every photo shrunk, the portrait also turned
  const ImageInputs inputs = prepare_images(photos, dir / "staged", options, null_reporter());
  ASSERT_EQ(inputs.images.size(), 3u);
  for (const StagedImage& image : inputs.images) {
    ASSERT_TRUE(image.rewritten) << image.name;
    const std::string bytes = hos::testing::read_text(dir / "staged" / image.name);
    EXPECT_EQ(hos::testing::jpeg_sampling_factors(bytes), (std::vector<int>{0x11, 0x11, 0x11})) << image.name;
  }
}

// A phone stores a portrait photo sideways with EXIF orientation 6, and hos
// stages it turned upright. Re-encoding it at JPEG quality 95 moved the
// keypoints of a dark synthetic capture enough to raise its SfM rotation
// errors from 0.063 to 0.077 degrees (0.068 at quality 100); the turned
// copy must keep the photo's pixels nearly exactly.
TEST(StagedCopies, TurnedJpegKeepsThePhotosPixels) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  fs::create_directories(photos);
  // Fine dark texture, as in a dim scene: noise blurred to the scale of
  // SIFT's keypoints.
  cv::Mat noise(480, 640, CV_8UC3), texture;
  cv::theRNG().state = 7;
  cv::randu(noise, cv::Scalar::all(0), cv::Scalar::all(80));
  cv::GaussianBlur(noise, texture, cv::Size(0, 0), 1.2);
  cv::Mat sideways;
  cv::rotate(texture, sideways, cv::ROTATE_90_COUNTERCLOCKWISE);
  const std::vector<std::uint8_t> stored = testing::jpeg_with_exif(sideways, 6, 24.0, true);
  testing::write_bytes(photos / "portrait.jpg", stored);
  testing::write_bytes(photos / "a.jpg", testing::jpeg_with_exif(texture, 1, 24.0, true));
  testing::write_bytes(photos / "b.jpg", testing::jpeg_with_exif(texture, 1, 24.0, true));
  const ImageInputs inputs = prepare_images(photos, dir / "staged", SfmOptions{}, null_reporter());
  const auto portrait = std::find_if(inputs.images.begin(), inputs.images.end(),
                                     [](const StagedImage& image) { return image.name == "portrait.jpg"; });
  ASSERT_NE(portrait, inputs.images.end());
  ASSERT_TRUE(portrait->rewritten);
  // The pixels hos starts from: the stored photo decoded and turned.
  cv::Mat upright;
  cv::rotate(cv::imdecode(stored, cv::IMREAD_COLOR | cv::IMREAD_IGNORE_ORIENTATION), upright, cv::ROTATE_90_CLOCKWISE);
  const cv::Mat staged = cv::imread((dir / "staged" / "portrait.jpg").string(), cv::IMREAD_COLOR);
  ASSERT_EQ(staged.size(), upright.size());
  // Quality 95 gives 45.8 dB here.
  EXPECT_GT(cv::PSNR(staged, upright), 50.0);
}

}  // namespace
}  // namespace hos::sfm
