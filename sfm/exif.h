// The EXIF fields the sfm stage needs from a JPEG: the orientation (so a
// photo taken in portrait is fed to COLMAP upright), the focal length (to
// decide whether all photos share one camera) and whether a GPS position is
// present (to match photos by position, COLMAP's spatial matcher). A small reader of the TIFF
// structure inside the APP1 segment; nothing else of EXIF is interpreted.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace hos::sfm {

// A photo's EXIF GPS position (WGS84).
struct GpsPosition {
  double latitude_deg = 0.0;         // north positive
  double longitude_deg = 0.0;        // east positive
  std::optional<double> altitude_m;  // above sea level; many phones omit it
};

struct ExifInfo {
  int orientation = 1;  // 1..8 as EXIF defines it; 1 = upright
  std::optional<double> focal_length_mm;
  std::optional<GpsPosition> gps;  // GPS IFD with latitude and longitude
  std::string camera_make;         // EXIF Make, trimmed; empty when absent
  std::string camera_model;        // EXIF Model, trimmed; empty when absent
};

// Parses EXIF from the bytes of a JPEG file. Files without EXIF (or not
// JPEG) give the defaults; malformed EXIF is ignored, never fatal.
ExifInfo parse_jpeg_exif(const std::vector<std::uint8_t>& jpeg);

// True if the JPEG's structure is complete: the markers up to the first
// start-of-scan are well formed and an end-of-image marker follows the scan
// data. A truncated download or copy fails this check even though decoders
// often return a partly grey image without an error.
bool jpeg_is_complete(const std::vector<std::uint8_t>& jpeg);

// Reads a whole file; throws InputError if it cannot be read.
std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& path);

}  // namespace hos::sfm
