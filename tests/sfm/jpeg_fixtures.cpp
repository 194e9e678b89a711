#include "tests/sfm/jpeg_fixtures.h"

#include <cmath>
#include <opencv2/imgcodecs.hpp>

namespace hos::sfm::testing {
namespace {

class TiffWriter {
 public:
  explicit TiffWriter(bool little) : little_(little) {}
  void u16(std::uint16_t v) {
    if (little_) {
      bytes.push_back(v & 0xFF);
      bytes.push_back(v >> 8);
    } else {
      bytes.push_back(v >> 8);
      bytes.push_back(v & 0xFF);
    }
  }
  void u32(std::uint32_t v) {
    if (little_) {
      u16(v & 0xFFFF);
      u16(v >> 16);
    } else {
      u16(v >> 16);
      u16(v & 0xFFFF);
    }
  }
  std::vector<std::uint8_t> bytes;

 private:
  bool little_;
};

// A TIFF block's header: byte order, 42, IFD0 right after (offset 8).
TiffWriter tiff_header(bool little_endian) {
  TiffWriter t(little_endian);
  t.bytes = little_endian ? std::vector<std::uint8_t>{'I', 'I'} : std::vector<std::uint8_t>{'M', 'M'};
  t.u16(42);
  t.u32(8);
  return t;
}

// Inserts the TIFF block as an APP1 EXIF segment right after the SOI marker.
void insert_exif(const std::vector<std::uint8_t>& tiff, std::vector<std::uint8_t>& jpeg) {
  std::vector<std::uint8_t> app1{0xFF, 0xE1, 0, 0, 'E', 'x', 'i', 'f', 0, 0};
  app1.insert(app1.end(), tiff.begin(), tiff.end());
  const std::size_t length = app1.size() - 2;
  app1[2] = static_cast<std::uint8_t>(length >> 8);
  app1[3] = static_cast<std::uint8_t>(length & 0xFF);
  jpeg.insert(jpeg.begin() + 2, app1.begin(), app1.end());
}

}  // namespace

cv::Mat gradient_image(int width, int height) {
  cv::Mat image(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      image.at<cv::Vec3b>(y, x) =
          cv::Vec3b(static_cast<std::uint8_t>(255 * x / width), static_cast<std::uint8_t>(255 * y / height), 40);
    }
  }
  return image;
}

std::vector<std::uint8_t> jpeg_with_exif(const cv::Mat& image, int orientation, double focal_mm, bool little_endian) {
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", image, jpeg, {cv::IMWRITE_JPEG_QUALITY, 98});
  // TIFF: header, IFD0 {orientation, exif pointer}, EXIF IFD {focal}, rational.
  TiffWriter t = tiff_header(little_endian);
  t.u16(2);  // IFD0 entries
  t.u16(0x0112);
  t.u16(3);
  t.u32(1);
  t.u16(static_cast<std::uint16_t>(orientation));
  t.u16(0);
  t.u16(0x8769);
  t.u16(4);
  t.u32(1);
  const std::uint32_t exif_ifd = 8 + 2 + 2 * 12 + 4;
  t.u32(exif_ifd);
  t.u32(0);  // no next IFD
  t.u16(focal_mm > 0 ? 1 : 0);
  const std::uint32_t rational_at = exif_ifd + 2 + (focal_mm > 0 ? 12 : 0) + 4;
  if (focal_mm > 0) {
    t.u16(0x920A);
    t.u16(5);
    t.u32(1);
    t.u32(rational_at);
  }
  t.u32(0);
  if (focal_mm > 0) {
    t.u32(static_cast<std::uint32_t>(std::lround(focal_mm * 1000)));
    t.u32(1000);
  }
  insert_exif(t.bytes, jpeg);
  return jpeg;
}

std::vector<std::uint8_t> jpeg_with_gps(const cv::Mat& image, bool little_endian) {
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", image, jpeg, {cv::IMWRITE_JPEG_QUALITY, 98});
  // TIFF: header, IFD0 {GPS pointer}, GPS IFD {latitude, longitude}, 6 rationals.
  TiffWriter t = tiff_header(little_endian);
  t.u16(1);
  t.u16(0x8825);
  t.u16(4);
  t.u32(1);
  const std::uint32_t gps_ifd = 8 + 2 + 12 + 4;
  t.u32(gps_ifd);
  t.u32(0);
  const std::uint32_t rationals = gps_ifd + 2 + 2 * 12 + 4;
  t.u16(2);
  for (std::uint16_t tag : {std::uint16_t{0x0002}, std::uint16_t{0x0004}}) {
    t.u16(tag);
    t.u16(5);
    t.u32(3);
    t.u32(rationals + (tag == 0x0002 ? 0 : 24));
  }
  t.u32(0);
  for (std::uint32_t value : {46u, 31u, 12u, 6u, 38u, 5u}) {  // 46 31' 12" N, 6 38' 5" E
    t.u32(value);
    t.u32(1);
  }
  insert_exif(t.bytes, jpeg);
  return jpeg;
}

}  // namespace hos::sfm::testing
