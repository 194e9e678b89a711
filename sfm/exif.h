// A photo's EXIF: the fields the sfm stage needs (orientation, so a photo
// taken in portrait is fed to COLMAP upright; focal length and camera make and
// model, to group photos into cameras; GPS position, for spatial matching and
// placement), and the whole block, kept so every staged copy carries it.
// Reading and writing go through libexiv2.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/geodesy.h"

namespace Exiv2 {
class ExifData;
}

namespace hos::sfm {

// A photo's EXIF GPS position (WGS84; the altitude above sea level, often
// missing from phones' photos).
using GpsPosition = GeoPosition;

struct ExifInfo {
  int orientation = 1;  // 1..8 as EXIF defines it; 1 = upright
  std::optional<double> focal_length_mm;
  std::optional<GpsPosition> gps;  // GPS IFD with latitude and longitude
  std::string camera_make;         // EXIF Make, trimmed; empty when absent
  std::string camera_model;        // EXIF Model, trimmed; empty when absent
};

// The whole EXIF block of one photo (empty when it has none).
class ExifBlock {
 public:
  ExifBlock();
  ~ExifBlock();
  ExifBlock(ExifBlock&&) noexcept;
  ExifBlock& operator=(ExifBlock&&) noexcept;
  ExifBlock(const ExifBlock&) = delete;
  ExifBlock& operator=(const ExifBlock&) = delete;

  bool empty() const;
  // The fields the stage uses; malformed values are left at their defaults.
  ExifInfo info() const;

  const Exiv2::ExifData& data() const { return *data_; }
  Exiv2::ExifData& data() { return *data_; }

 private:
  std::unique_ptr<Exiv2::ExifData> data_;
};

// The EXIF of a photo file's bytes (JPEG, PNG, TIFF, ...: whatever exiv2
// recognises). Files without EXIF give an empty block; malformed EXIF is
// ignored, never fatal.
ExifBlock read_exif(const std::vector<std::uint8_t>& file_bytes);

// The EXIF of a bare TIFF structure (as a HEIF file's Exif item holds it,
// after its offset field); malformed data gives an empty block.
ExifBlock read_exif_tiff(const std::uint8_t* tiff, std::size_t size);

// read_exif(jpeg).info().
ExifInfo parse_jpeg_exif(const std::vector<std::uint8_t>& jpeg);

// What changed between a photo and its staged copy, for the copy's EXIF.
struct StagedCopyChanges {
  int width = 0;  // the copy's size in pixels
  int height = 0;
  double scale = 1.0;                // copy pixels per original pixel (downscaling)
  bool transposed = false;           // turned by 90 degrees (width and height swapped)
  bool write_zero_altitude = false;  // GPS without altitude: write 0 m so COLMAP takes the position
};

// Writes the original's EXIF into the staged copy (a JPEG, PNG or TIFF file
// already written): Orientation 1 (the copy's pixels are upright), the
// copy's pixel size, the focal plane resolution scaled with the pixels, no
// stale thumbnail. Throws OutputError naming the copy.
void write_staged_exif(const ExifBlock& original, const StagedCopyChanges& changes, const std::filesystem::path& copy);

// True if the JPEG's structure is complete: the markers up to the first
// start-of-scan are well formed and an end-of-image marker follows the scan
// data. A truncated download or copy fails this check even though decoders
// often return a partly grey image without an error.
bool jpeg_is_complete(const std::vector<std::uint8_t>& jpeg);

// Reads a whole file; throws InputError if it cannot be read.
std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& path);

}  // namespace hos::sfm
