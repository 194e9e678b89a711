#include "texture/image_encoding.h"

#include <jpeglib.h>

#include <cstdio>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/error.h"

namespace hos::texture {

namespace {

// libjpeg reports errors through a callback that must not return.
struct JpegError {
  jpeg_error_mgr manager;
  char message[JMSG_LENGTH_MAX];
};

[[noreturn]] void throw_jpeg_error(j_common_ptr info) {
  auto* error = reinterpret_cast<JpegError*>(info->err);
  (*info->err->format_message)(info, error->message);
  throw std::runtime_error(std::string("JPEG encoding failed: ") + error->message);
}

std::vector<unsigned char> encode_jpeg(const cv::Mat& bgr, int quality) {
  jpeg_compress_struct info{};
  JpegError error{};
  info.err = jpeg_std_error(&error.manager);
  error.manager.error_exit = throw_jpeg_error;
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  std::vector<unsigned char> out;
  try {
    jpeg_create_compress(&info);
    jpeg_mem_dest(&info, &buffer, &size);
    info.image_width = static_cast<JDIMENSION>(bgr.cols);
    info.image_height = static_cast<JDIMENSION>(bgr.rows);
    info.input_components = 3;
    info.in_color_space = JCS_RGB;
    jpeg_set_defaults(&info);
    jpeg_set_quality(&info, quality, TRUE);
    for (int c = 0; c < 3; ++c) info.comp_info[c].h_samp_factor = info.comp_info[c].v_samp_factor = 1;  // 4:4:4
    info.optimize_coding = TRUE;
    jpeg_start_compress(&info, TRUE);
    std::vector<unsigned char> row(static_cast<std::size_t>(bgr.cols) * 3);
    while (info.next_scanline < info.image_height) {
      const cv::Vec3b* src = bgr.ptr<cv::Vec3b>(static_cast<int>(info.next_scanline));
      for (int x = 0; x < bgr.cols; ++x) {
        row[3 * x] = src[x][2];
        row[3 * x + 1] = src[x][1];
        row[3 * x + 2] = src[x][0];
      }
      JSAMPROW rows[1] = {row.data()};
      jpeg_write_scanlines(&info, rows, 1);
    }
    jpeg_finish_compress(&info);
    out.assign(buffer, buffer + size);
  } catch (...) {
    jpeg_destroy_compress(&info);
    std::free(buffer);
    throw;
  }
  jpeg_destroy_compress(&info);
  std::free(buffer);
  return out;
}

}  // namespace

EncodedImage encode_image(const cv::Mat& bgr, const std::string& format, int jpeg_quality) {
  if (bgr.type() != CV_8UC3 || bgr.empty()) throw std::invalid_argument("encode_image: expected a non-empty BGR image");
  EncodedImage image;
  if (format == "jpeg") {
    image.bytes = encode_jpeg(bgr, jpeg_quality);
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
    if (!out) throw OutputError(path.string(), "cannot open for writing");
    out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.flush();
    if (!out) throw OutputError(path.string(), "write failed");
  });
}

}  // namespace hos::texture
