#include "sfm/exif.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "tests/sfm/jpeg_fixtures.h"

namespace hos::sfm {
namespace {

TEST(Exif, ReadsOrientationAndFocalLengthInBothByteOrders) {
  for (bool little_endian : {true, false}) {
    const auto jpeg = testing::jpeg_with_exif(testing::gradient_image(64, 48), 6, 35.5, little_endian);
    const ExifInfo info = parse_jpeg_exif(jpeg);
    EXPECT_EQ(info.orientation, 6);
    ASSERT_TRUE(info.focal_length_mm.has_value());
    EXPECT_DOUBLE_EQ(*info.focal_length_mm, 35.5);
  }
}

TEST(Exif, GpsPositionIsDetectedInBothByteOrders) {
  for (bool little_endian : {true, false}) {
    EXPECT_TRUE(
        parse_jpeg_exif(testing::jpeg_with_gps(testing::gradient_image(64, 48), little_endian)).gps.has_value());
    // Orientation and focal length only: no position.
    EXPECT_FALSE(parse_jpeg_exif(testing::jpeg_with_exif(testing::gradient_image(64, 48), 1, 35.0, little_endian))
                     .gps.has_value());
  }
}

// A phone's EXIF as exiv2 writes it: make and model (padded as cameras pad
// them), GPS south and west with an altitude below sea level.
TEST(Exif, ReadsMakeModelAndSignedGpsWithAltitude) {
  testing::PhoneExif fields;
  fields.make = "Apple  ";
  fields.model = "iPhone 12 mini";
  fields.latitude_deg = -33.8568;
  fields.longitude_deg = -70.6483;
  fields.altitude_m = -12.5;
  const ExifInfo info = parse_jpeg_exif(testing::jpeg_with_phone_exif(testing::gradient_image(64, 48), fields));
  EXPECT_EQ(info.camera_make, "Apple");
  EXPECT_EQ(info.camera_model, "iPhone 12 mini");
  ASSERT_TRUE(info.focal_length_mm.has_value());
  EXPECT_NEAR(*info.focal_length_mm, 4.2, 1e-9);
  ASSERT_TRUE(info.gps.has_value());
  EXPECT_NEAR(info.gps->latitude_deg, -33.8568, 1e-6);
  EXPECT_NEAR(info.gps->longitude_deg, -70.6483, 1e-6);
  ASSERT_TRUE(info.gps->altitude_m.has_value());
  EXPECT_NEAR(*info.gps->altitude_m, -12.5, 1e-9);
}

TEST(Exif, GpsWithoutAltitudeHasNone) {
  testing::PhoneExif fields;
  fields.latitude_deg = 46.52;
  fields.longitude_deg = 6.63;
  const ExifInfo info = parse_jpeg_exif(testing::jpeg_with_phone_exif(testing::gradient_image(64, 48), fields));
  ASSERT_TRUE(info.gps.has_value());
  EXPECT_NEAR(info.gps->latitude_deg, 46.52, 1e-6);
  EXPECT_NEAR(info.gps->longitude_deg, 6.63, 1e-6);
  EXPECT_FALSE(info.gps->altitude_m.has_value());
}

// The hand-written fixture's position: 46 31' 12" N, 6 38' 5" E (no Ref tags:
// north and east).
TEST(Exif, GpsPositionValueFromDegreesMinutesSeconds) {
  const ExifInfo info = parse_jpeg_exif(testing::jpeg_with_gps(testing::gradient_image(64, 48), true));
  ASSERT_TRUE(info.gps.has_value());
  EXPECT_NEAR(info.gps->latitude_deg, 46.0 + 31.0 / 60 + 12.0 / 3600, 1e-9);
  EXPECT_NEAR(info.gps->longitude_deg, 6.0 + 38.0 / 60 + 5.0 / 3600, 1e-9);
}

TEST(Exif, NoExifGivesDefaults) {
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", testing::gradient_image(32, 32), jpeg);
  const ExifInfo info = parse_jpeg_exif(jpeg);
  EXPECT_EQ(info.orientation, 1);
  EXPECT_FALSE(info.focal_length_mm.has_value());
  EXPECT_FALSE(info.gps.has_value());
}

TEST(Exif, GarbageIsNotFatal) {
  std::vector<std::uint8_t> bytes(100, 0xFF);
  EXPECT_EQ(parse_jpeg_exif(bytes).orientation, 1);
  bytes = {0xFF, 0xD8, 0xFF, 0xE1, 0x00, 0x40, 'E', 'x', 'i', 'f', 0, 0, 'I', 'I', 42, 0, 0xFF, 0xFF, 0xFF, 0x7F};
  EXPECT_EQ(parse_jpeg_exif(bytes).orientation, 1);
}

TEST(Exif, CompleteJpegPassesTruncatedFails) {
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", testing::gradient_image(128, 96), jpeg);
  EXPECT_TRUE(jpeg_is_complete(jpeg));
  auto truncated = jpeg;
  truncated.resize(jpeg.size() * 2 / 3);
  EXPECT_FALSE(jpeg_is_complete(truncated));
  // An EXIF thumbnail's own end marker before the scan must not count.
  auto with_exif = testing::jpeg_with_exif(testing::gradient_image(128, 96), 1, 0.0, true);
  EXPECT_TRUE(jpeg_is_complete(with_exif));
  with_exif.resize(with_exif.size() - 10);
  EXPECT_FALSE(jpeg_is_complete(with_exif));
  EXPECT_FALSE(jpeg_is_complete({}));
}

}  // namespace
}  // namespace hos::sfm
