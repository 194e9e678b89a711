// Test images for the sfm tests: textured images and JPEGs carrying EXIF.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace hos::sfm::testing {

// A colour image whose pixels identify their position (no symmetry), so a
// rotation or flip is detectable.
cv::Mat gradient_image(int width, int height);

// JPEG bytes of image with an APP1 EXIF block holding the orientation and,
// if focal_mm > 0, the focal length.
std::vector<std::uint8_t> jpeg_with_exif(const cv::Mat& image, int orientation, double focal_mm, bool little_endian);

// JPEG bytes of image with an APP1 EXIF block holding only a GPS IFD with
// latitude and longitude (three rationals each).
std::vector<std::uint8_t> jpeg_with_gps(const cv::Mat& image, bool little_endian);

}  // namespace hos::sfm::testing
