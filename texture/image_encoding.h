// Encoding of the atlas images: PNG (lossless) or JPEG with full chroma
// resolution (core/jpeg_encoding.h; chroma subsampling would mix
// neighbouring charts' colours across the thin padding).
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace hos::texture {

struct EncodedImage {
  std::vector<unsigned char> bytes;
  std::string mime_type;  // image/png | image/jpeg
  std::string extension;  // .png | .jpg
};

// format "png" or "jpeg" (quality 1-100). Throws std::runtime_error if the
// image (CV_8UC3, BGR) cannot be encoded, std::invalid_argument for an
// unknown format.
EncodedImage encode_image(const cv::Mat& bgr, const std::string& format, int jpeg_quality);

// Writes the bytes to path atomically; throws OutputError naming the file.
void write_bytes(const std::filesystem::path& path, const void* data, std::size_t size);

}  // namespace hos::texture
