#include "core/jpeg_encoding.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"
#include "tests/support/test_support.h"

namespace hos {
namespace {

std::vector<int> factors(const std::vector<unsigned char>& jpeg) {
  return testing::jpeg_sampling_factors(std::string(jpeg.begin(), jpeg.end()));
}

// Stripes of saturated colours one pixel wide: what 4:2:0 smears.
cv::Mat colour_stripes() {
  cv::Mat image(64, 64, CV_8UC3);
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      image.at<cv::Vec3b>(y, x) = (x + y / 8) % 2 == 0 ? cv::Vec3b(40, 40, 220) : cv::Vec3b(60, 200, 60);
    }
  }
  return image;
}

TEST(JpegEncoding, KeepsFullChromaResolution) {
  const cv::Mat stripes = colour_stripes();
  const std::vector<unsigned char> full = encode_jpeg_444(stripes, 95);
  EXPECT_EQ(factors(full), (std::vector<int>{0x11, 0x11, 0x11}));
  std::vector<unsigned char> halved;
  ASSERT_TRUE(cv::imencode(".jpg", stripes, halved, {cv::IMWRITE_JPEG_QUALITY, 95}));
  EXPECT_NE(factors(halved), factors(full));  // OpenCV's 4:2:0, what this replaces
  const double psnr_full = cv::PSNR(stripes, cv::imdecode(full, cv::IMREAD_COLOR));
  const double psnr_halved = cv::PSNR(stripes, cv::imdecode(halved, cv::IMREAD_COLOR));
  std::cout << "[ figures  ] colour stripes at quality 95: " << psnr_full << " dB at 4:4:4, " << psnr_halved
            << " dB at OpenCV's 4:2:0\n";
  EXPECT_GT(psnr_full, psnr_halved + 6.0);
}

TEST(JpegEncoding, EncodesGreyImagesAndRefusesOtherTypes) {
  cv::Mat grey(32, 48, CV_8UC1);
  for (int y = 0; y < grey.rows; ++y)
    for (int x = 0; x < grey.cols; ++x) grey.at<unsigned char>(y, x) = static_cast<unsigned char>(4 * x + y);
  const std::vector<unsigned char> jpeg = encode_jpeg_444(grey, 95);
  EXPECT_EQ(factors(jpeg).size(), 1u);
  const cv::Mat decoded = cv::imdecode(jpeg, cv::IMREAD_UNCHANGED);
  ASSERT_EQ(decoded.type(), CV_8UC1);
  EXPECT_GT(cv::PSNR(grey, decoded), 40.0);
  EXPECT_THROW(encode_jpeg_444(cv::Mat(), 95), std::invalid_argument);
  EXPECT_THROW(encode_jpeg_444(cv::Mat(8, 8, CV_16UC3), 95), std::invalid_argument);
}

// A file that cannot be created (its folder is missing, or it is a folder)
// is an OutputError naming it and what it was (once: the error says "cannot
// write" itself); one that can holds the encoder's bytes.
TEST(JpegEncoding, AFileItCannotWriteIsAnOutputErrorNamingIt) {
  const testing::TempDir dir;
  const cv::Mat image = colour_stripes();
  for (const std::filesystem::path& file : {dir / "missing" / "frame.jpg", dir.path()}) {
    try {
      write_jpeg_444(image, 90, file, "the video frame");
      ADD_FAILURE() << file << ": no error";
    } catch (const OutputError& e) {
      EXPECT_EQ(std::string(e.what()), file.string() + ": cannot write: the video frame");
    }
  }
  write_jpeg_444(image, 90, dir / "frame.jpg", "the video frame");
  const std::vector<unsigned char> bytes = encode_jpeg_444(image, 90);
  EXPECT_EQ(testing::read_text(dir / "frame.jpg"), std::string(bytes.begin(), bytes.end()));
}

}  // namespace
}  // namespace hos
