// The copies hos-sfm re-encodes for COLMAP (turned by their EXIF
// orientation, shrunk, decoded from HEIC) keep the photo's colour detail.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

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

}  // namespace
}  // namespace hos::sfm
