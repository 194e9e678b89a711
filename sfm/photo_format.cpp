#include "sfm/photo_format.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>

namespace hos::sfm {
namespace {

bool starts_with(const std::uint8_t* head, std::size_t size, const char* magic, std::size_t n) {
  return size >= n && std::memcmp(head, magic, n) == 0;
}

// BMP's "BM" is short; the DIB header size that follows must be one of the
// known ones.
bool is_bmp(const std::uint8_t* head, std::size_t size) {
  if (!starts_with(head, size, "BM", 2) || size < 18) return false;
  const std::uint32_t dib = head[14] | head[15] << 8 | head[16] << 16 | std::uint32_t(head[17]) << 24;
  return dib == 12 || dib == 40 || dib == 52 || dib == 56 || dib == 64 || dib == 108 || dib == 124;
}

// An ISO base media file whose ftyp box names a HEIF brand (HEIC from
// phones, AVIF, plain HEIF) as its major or a compatible brand.
bool is_heif(const std::uint8_t* head, std::size_t size) {
  if (size < 16 || std::memcmp(head + 4, "ftyp", 4) != 0) return false;
  static constexpr std::array<const char*, 10> kBrands{"heic", "heix", "heim", "heis", "hevc",
                                                       "hevx", "mif1", "msf1", "heif", "avif"};
  const std::size_t box = head[0] << 24 | head[1] << 16 | head[2] << 8 | head[3];
  const std::size_t end = std::min(size, std::max<std::size_t>(box, 16));
  auto is_brand = [&](std::size_t at) {
    return std::any_of(kBrands.begin(), kBrands.end(),
                       [&](const char* brand) { return std::memcmp(head + at, brand, 4) == 0; });
  };
  if (is_brand(8)) return true;
  for (std::size_t at = 16; at + 4 <= end; at += 4) {  // compatible brands
    if (is_brand(at)) return true;
  }
  return false;
}

}  // namespace

PhotoFormat photo_format_of(const std::uint8_t* head, std::size_t size) {
  if (starts_with(head, size, "\xFF\xD8\xFF", 3)) return PhotoFormat::kJpeg;
  if (starts_with(head, size, "\x89PNG\r\n\x1A\n", 8)) return PhotoFormat::kPng;
  if (starts_with(head, size, "II*\0", 4) || starts_with(head, size, "MM\0*", 4) ||
      starts_with(head, size, "II+\0", 4) || starts_with(head, size, "MM\0+", 4)) {
    return PhotoFormat::kTiff;  // classic and BigTIFF
  }
  if (is_bmp(head, size)) return PhotoFormat::kBmp;
  if (is_heif(head, size)) return PhotoFormat::kHeif;
  return PhotoFormat::kUnknown;
}

PhotoFormat photo_format_of_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return PhotoFormat::kUnknown;
  std::array<char, kPhotoFormatHeadBytes> head{};
  in.read(head.data(), head.size());
  return photo_format_of(reinterpret_cast<const std::uint8_t*>(head.data()), static_cast<std::size_t>(in.gcount()));
}

std::string photo_format_name(PhotoFormat format) {
  switch (format) {
    case PhotoFormat::kJpeg:
      return "JPEG";
    case PhotoFormat::kPng:
      return "PNG";
    case PhotoFormat::kTiff:
      return "TIFF";
    case PhotoFormat::kBmp:
      return "BMP";
    case PhotoFormat::kHeif:
      return "HEIF";
    case PhotoFormat::kUnknown:
      break;
  }
  return "unknown";
}

}  // namespace hos::sfm
