#include "tests/sfm/jpeg_fixtures.h"

#include <libheif/heif.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

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

namespace {

// Degrees as degrees, minutes and seconds (three rationals).
Exiv2::URationalValue dms(double degrees) {
  const double a = std::abs(degrees);
  const auto d = static_cast<std::uint32_t>(a);
  const auto m = static_cast<std::uint32_t>((a - d) * 60.0);
  const double sec = (a - d - m / 60.0) * 3600.0;
  Exiv2::URationalValue v;
  v.value_ = {{d, 1}, {m, 1}, {static_cast<std::uint32_t>(std::lround(sec * 10000.0)), 10000}};
  return v;
}

}  // namespace

Exiv2::ExifData exif_data(const PhoneExif& f) {
  Exiv2::ExifData exif;
  exif["Exif.Image.Orientation"] = static_cast<std::uint16_t>(f.orientation);
  if (!f.make.empty()) exif["Exif.Image.Make"] = f.make;
  if (!f.model.empty()) exif["Exif.Image.Model"] = f.model;
  if (f.focal_mm > 0) {
    exif["Exif.Photo.FocalLength"] = Exiv2::URational(static_cast<std::uint32_t>(std::lround(f.focal_mm * 100.0)), 100);
  }
  if (f.focal_35mm > 0) exif["Exif.Photo.FocalLengthIn35mmFilm"] = static_cast<std::uint16_t>(f.focal_35mm);
  if (f.focal_plane_x_resolution > 0) {
    const Exiv2::URational r(static_cast<std::uint32_t>(std::lround(f.focal_plane_x_resolution)), 1);
    exif["Exif.Photo.FocalPlaneXResolution"] = r;
    exif["Exif.Photo.FocalPlaneYResolution"] = r;
    exif["Exif.Photo.FocalPlaneResolutionUnit"] = std::uint16_t{2};  // inch
  }
  if (f.latitude_deg && f.longitude_deg) {
    exif["Exif.GPSInfo.GPSLatitudeRef"] = std::string(*f.latitude_deg < 0 ? "S" : "N");
    exif["Exif.GPSInfo.GPSLatitude"] = dms(*f.latitude_deg);
    exif["Exif.GPSInfo.GPSLongitudeRef"] = std::string(*f.longitude_deg < 0 ? "W" : "E");
    exif["Exif.GPSInfo.GPSLongitude"] = dms(*f.longitude_deg);
  }
  if (f.altitude_m) {
    exif["Exif.GPSInfo.GPSAltitudeRef"] = std::string(*f.altitude_m < 0 ? "1" : "0");
    exif["Exif.GPSInfo.GPSAltitude"] =
        Exiv2::URational(static_cast<std::uint32_t>(std::lround(std::abs(*f.altitude_m) * 100.0)), 100);
  }
  return exif;
}

Exiv2::ExifData read_exif_data(const std::filesystem::path& file) {
  auto image = Exiv2::ImageFactory::open(file.string());
  image->readMetadata();
  return image->exifData();
}

void write_phone_exif(const std::filesystem::path& file, const PhoneExif& fields) {
  auto image = Exiv2::ImageFactory::open(file.string());
  image->readMetadata();
  image->setExifData(exif_data(fields));
  image->writeMetadata();
}

void write_bytes(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error(path.string() + ": could not write");
}

std::vector<std::uint8_t> jpeg_with_phone_exif(const cv::Mat& image, const PhoneExif& fields) {
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", image, jpeg, {cv::IMWRITE_JPEG_QUALITY, 98});
  auto io = Exiv2::ImageFactory::open(jpeg.data(), static_cast<long>(jpeg.size()));
  io->readMetadata();
  io->setExifData(exif_data(fields));
  io->writeMetadata();
  Exiv2::BasicIo& mem = io->io();
  mem.seek(0, Exiv2::BasicIo::beg);
  const Exiv2::DataBuf buf = mem.read(static_cast<long>(mem.size()));
  return std::vector<std::uint8_t>(buf.pData_, buf.pData_ + buf.size_);
}

namespace {

struct HeifContextFree {
  void operator()(heif_context* c) const { heif_context_free(c); }
};
struct HeifImageRelease {
  void operator()(heif_image* i) const { heif_image_release(i); }
};

heif_error append_bytes(heif_context*, const void* data, size_t size, void* userdata) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(userdata);
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  out->insert(out->end(), bytes, bytes + size);
  return heif_error{heif_error_Ok, heif_suberror_Unspecified, "ok"};
}

void check(heif_error error) {
  if (error.code != heif_error_Ok) throw std::runtime_error(std::string("libheif: ") + error.message);
}

}  // namespace

std::vector<std::uint8_t> heic_with_exif(const cv::Mat& image, int orientation, const PhoneExif& fields) {
  const std::unique_ptr<heif_context, HeifContextFree> context(heif_context_alloc());
  heif_encoder* encoder = nullptr;
  if (heif_context_get_encoder_for_format(context.get(), heif_compression_HEVC, &encoder).code != heif_error_Ok) {
    return {};
  }
  heif_encoder_set_lossy_quality(encoder, 95);
  heif_image* raw = nullptr;
  check(heif_image_create(image.cols, image.rows, heif_colorspace_RGB, heif_chroma_interleaved_RGB, &raw));
  const std::unique_ptr<heif_image, HeifImageRelease> rgb(raw);
  check(heif_image_add_plane(rgb.get(), heif_channel_interleaved, image.cols, image.rows, 8));
  int stride = 0;
  std::uint8_t* plane = heif_image_get_plane(rgb.get(), heif_channel_interleaved, &stride);
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b& bgr = image.at<cv::Vec3b>(y, x);
      std::uint8_t* p = plane + y * stride + 3 * x;
      p[0] = bgr[2];
      p[1] = bgr[1];
      p[2] = bgr[0];
    }
  }
  heif_encoding_options* options = heif_encoding_options_alloc();
  options->image_orientation = static_cast<heif_orientation>(orientation);
  heif_image_handle* handle = nullptr;
  const heif_error encoded = heif_context_encode_image(context.get(), rgb.get(), encoder, options, &handle);
  heif_encoding_options_free(options);
  heif_encoder_release(encoder);
  check(encoded);
  Exiv2::Blob tiff;
  Exiv2::ExifParser::encode(tiff, nullptr, 0, Exiv2::littleEndian, exif_data(fields));
  const heif_error exif =
      heif_context_add_exif_metadata(context.get(), handle, tiff.data(), static_cast<int>(tiff.size()));
  heif_image_handle_release(handle);
  check(exif);
  std::vector<std::uint8_t> bytes;
  heif_writer writer{1, &append_bytes};
  check(heif_context_write(context.get(), &writer, &bytes));
  return bytes;
}

}  // namespace hos::sfm::testing
