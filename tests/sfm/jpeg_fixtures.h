// Test images for the sfm tests: textured images, JPEGs carrying EXIF and
// HEIC photos (encoded at run time with libheif's HEVC encoder).
#pragma once

#include <cstdint>
#include <exiv2/exiv2.hpp>
#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
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

// The EXIF fields a phone writes, for fixtures made with exiv2.
struct PhoneExif {
  int orientation = 1;
  double focal_mm = 4.2;
  int focal_35mm = 26;  // FocalLengthIn35mmFilm; 0 = absent
  std::string make = "Apple";
  std::string model = "iPhone 12";
  std::optional<double> latitude_deg;  // signed; written as a value and N/S
  std::optional<double> longitude_deg;
  std::optional<double> altitude_m;       // signed; written with AltitudeRef
  double focal_plane_x_resolution = 0.0;  // pixels per inch on the sensor; 0 = absent
};

Exiv2::ExifData exif_data(const PhoneExif& fields);

// Writes a fixture's bytes to path (its folder made first); throws
// std::runtime_error naming the file when it cannot.
void write_bytes(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes);

// JPEG bytes of image carrying fields as EXIF.
std::vector<std::uint8_t> jpeg_with_phone_exif(const cv::Mat& image, const PhoneExif& fields);

// Writes fields as EXIF into an existing image file (JPEG, PNG, TIFF).
void write_phone_exif(const std::filesystem::path& file, const PhoneExif& fields);

// The EXIF of an image file, read with exiv2 (empty when none).
Exiv2::ExifData read_exif_data(const std::filesystem::path& file);

// HEIC bytes: image (BGR, 8 bits) encoded as HEVC, displayed turned by the
// EXIF-style orientation (stored as the HEIF irot/imir transforms), with
// fields as its Exif item. Empty when libheif has no HEVC encoder.
std::vector<std::uint8_t> heic_with_exif(const cv::Mat& image, int orientation, const PhoneExif& fields);

}  // namespace hos::sfm::testing
