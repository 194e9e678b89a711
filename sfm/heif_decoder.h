// HEIC/HEIF photos (the iPhone's default format, AVIF too) through libheif:
// the primary image, upright, and its EXIF block.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "sfm/exif.h"

namespace hos::sfm {

struct HeifPhoto {
  // 8 bits per channel, BGR, upright: libheif applies the file's rotation and
  // mirroring (irot, imir) itself, so the EXIF orientation, which describes
  // the same turn, must not be applied again.
  cv::Mat image;
  ExifBlock exif;  // empty when the file has no Exif item
};

// Decodes the file's primary image; on failure returns nothing and sets
// reason (libheif's message). Never throws for bad data.
std::optional<HeifPhoto> decode_heif(const std::vector<std::uint8_t>& bytes, std::string& reason);

}  // namespace hos::sfm
