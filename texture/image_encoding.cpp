#include "texture/image_encoding.h"

#include <cstdio>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/jpeg_encoding.h"

namespace hos::texture {

EncodedImage encode_image(const cv::Mat& bgr, const std::string& format, int jpeg_quality) {
  if (bgr.type() != CV_8UC3 || bgr.empty()) throw std::invalid_argument("encode_image: expected a non-empty BGR image");
  EncodedImage image;
  if (format == "jpeg") {
    image.bytes = encode_jpeg_444(bgr, jpeg_quality);
    image.mime_type = "image/jpeg";
    image.extension = ".jpg";
  } else if (format == "png") {
    if (!cv::imencode(".png", bgr, image.bytes)) throw std::runtime_error("PNG encoding failed");
    image.mime_type = "image/png";
    image.extension = ".png";
  } else {
    throw std::invalid_argument("encode_image: unknown format " + format);
  }
  return image;
}

void write_bytes(const std::filesystem::path& path, const void* data, std::size_t size) {
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw OutputError(path.string(), "the file does not open for writing");
    out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.flush();
    if (!out) throw OutputError(path.string(), "write failed");
  });
}

}  // namespace hos::texture
