#include "sfm/exif.h"

#include <fstream>
#include <iterator>

#include "core/error.h"

namespace hos::sfm {
namespace {

constexpr std::uint16_t kTagOrientation = 0x0112;
constexpr std::uint16_t kTagExifIfd = 0x8769;
constexpr std::uint16_t kTagFocalLength = 0x920A;
constexpr std::uint16_t kTagGpsIfd = 0x8825;
constexpr std::uint16_t kTagGpsLatitude = 0x0002;
constexpr std::uint16_t kTagGpsLongitude = 0x0004;
constexpr std::uint16_t kTypeShort = 3;
constexpr std::uint16_t kTypeLong = 4;
constexpr std::uint16_t kTypeRational = 5;

// Bounds-checked reads from the TIFF block with its byte order.
class TiffReader {
 public:
  TiffReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {
    if (size_ >= 8 && data_[0] == 'I' && data_[1] == 'I') {
      little_ = true;
      valid_ = u16(2) == 42;
    } else if (size_ >= 8 && data_[0] == 'M' && data_[1] == 'M') {
      little_ = false;
      valid_ = u16(2) == 42;
    }
  }
  bool valid() const { return valid_; }
  bool has(std::size_t offset, std::size_t n) const { return offset <= size_ && n <= size_ - offset; }
  std::uint16_t u16(std::size_t o) const {
    if (!has(o, 2)) return 0;
    return little_ ? static_cast<std::uint16_t>(data_[o] | data_[o + 1] << 8)
                   : static_cast<std::uint16_t>(data_[o] << 8 | data_[o + 1]);
  }
  std::uint32_t u32(std::size_t o) const {
    if (!has(o, 4)) return 0;
    return little_ ? (std::uint32_t(u16(o)) | std::uint32_t(u16(o + 2)) << 16)
                   : (std::uint32_t(u16(o)) << 16 | std::uint32_t(u16(o + 2)));
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  bool little_ = true;
  bool valid_ = false;
};

// Visits the 12-byte entries of the IFD at offset.
template <typename Visit>
void for_each_entry(const TiffReader& tiff, std::size_t ifd, Visit visit) {
  if (!tiff.has(ifd, 2)) return;
  const std::uint16_t count = tiff.u16(ifd);
  for (std::uint16_t i = 0; i < count; ++i) {
    const std::size_t entry = ifd + 2 + 12u * i;
    if (!tiff.has(entry, 12)) return;
    visit(tiff.u16(entry), tiff.u16(entry + 2), entry + 8);
  }
}

void parse_tiff(const std::uint8_t* data, std::size_t size, ExifInfo& info) {
  const TiffReader tiff(data, size);
  if (!tiff.valid()) return;
  std::size_t exif_ifd = 0;
  std::size_t gps_ifd = 0;
  for_each_entry(tiff, tiff.u32(4), [&](std::uint16_t tag, std::uint16_t type, std::size_t value) {
    if (tag == kTagOrientation && type == kTypeShort) {
      const int o = tiff.u16(value);
      if (o >= 1 && o <= 8) info.orientation = o;
    } else if (tag == kTagExifIfd && type == kTypeLong) {
      exif_ifd = tiff.u32(value);
    } else if (tag == kTagGpsIfd && type == kTypeLong) {
      gps_ifd = tiff.u32(value);
    }
  });
  if (gps_ifd != 0) {
    // Latitude and longitude are each three rationals (degrees, minutes, seconds).
    bool latitude = false, longitude = false;
    for_each_entry(tiff, gps_ifd, [&](std::uint16_t tag, std::uint16_t type, std::size_t) {
      if (type != kTypeRational) return;
      latitude = latitude || tag == kTagGpsLatitude;
      longitude = longitude || tag == kTagGpsLongitude;
    });
    if (latitude && longitude) info.gps = GpsPosition{};
  }
  if (exif_ifd == 0) return;
  for_each_entry(tiff, exif_ifd, [&](std::uint16_t tag, std::uint16_t type, std::size_t value) {
    if (tag != kTagFocalLength || type != kTypeRational) return;
    const std::size_t at = tiff.u32(value);  // rationals live at an offset
    const std::uint32_t num = tiff.u32(at);
    const std::uint32_t den = tiff.u32(at + 4);
    if (tiff.has(at, 8) && den != 0 && num != 0) info.focal_length_mm = double(num) / double(den);
  });
}

// Walks the marker segments before the scan data. Calls visit(marker,
// payload offset, payload size) for each; returns the offset just after the
// SOS segment header, or 0 if the structure is broken before that.
template <typename Visit>
std::size_t walk_segments(const std::vector<std::uint8_t>& jpeg, Visit visit) {
  if (jpeg.size() < 4 || jpeg[0] != 0xFF || jpeg[1] != 0xD8) return 0;
  std::size_t pos = 2;
  while (pos + 4 <= jpeg.size()) {
    if (jpeg[pos] != 0xFF) return 0;
    const std::uint8_t marker = jpeg[pos + 1];
    if (marker == 0xFF) {  // fill byte
      ++pos;
      continue;
    }
    const std::size_t length = std::size_t(jpeg[pos + 2]) << 8 | jpeg[pos + 3];
    if (length < 2 || pos + 2 + length > jpeg.size()) return 0;
    visit(marker, pos + 4, length - 2);
    pos += 2 + length;
    if (marker == 0xDA) return pos;
  }
  return 0;
}

}  // namespace

ExifInfo parse_jpeg_exif(const std::vector<std::uint8_t>& jpeg) {
  ExifInfo info;
  walk_segments(jpeg, [&](std::uint8_t marker, std::size_t offset, std::size_t size) {
    static constexpr char kHeader[] = {'E', 'x', 'i', 'f', 0, 0};
    if (marker != 0xE1 || size < 6 + 8) return;
    if (!std::equal(kHeader, kHeader + 6, jpeg.begin() + static_cast<std::ptrdiff_t>(offset))) return;
    parse_tiff(jpeg.data() + offset + 6, size - 6, info);
  });
  return info;
}

bool jpeg_is_complete(const std::vector<std::uint8_t>& jpeg) {
  const std::size_t scan = walk_segments(jpeg, [](std::uint8_t, std::size_t, std::size_t) {});
  if (scan == 0) return false;
  // In entropy-coded data 0xFF is always followed by 0x00 or a restart
  // marker, so the first FF D9 after the scan header is the end of image.
  for (std::size_t i = scan; i + 1 < jpeg.size(); ++i) {
    if (jpeg[i] == 0xFF && jpeg[i + 1] == 0xD9) return true;
  }
  return false;
}

std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "cannot be opened for reading");
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(path.string(), "read error");
  return bytes;
}

}  // namespace hos::sfm
