#include "core/jpeg_encoding.h"

#include <jpeglib.h>

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"

namespace hos {

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

// Writes the image's rows (BGR turned to RGB) into the started compression.
void write_rows(jpeg_compress_struct& info, const cv::Mat& image) {
  const int channels = image.channels();
  std::vector<unsigned char> row(static_cast<std::size_t>(image.cols) * channels);
  while (info.next_scanline < info.image_height) {
    const unsigned char* src = image.ptr<unsigned char>(static_cast<int>(info.next_scanline));
    if (channels == 1) {
      std::copy(src, src + image.cols, row.begin());
    } else {
      for (int x = 0; x < image.cols; ++x) {
        row[3 * x] = src[3 * x + 2];
        row[3 * x + 1] = src[3 * x + 1];
        row[3 * x + 2] = src[3 * x];
      }
    }
    JSAMPROW rows[1] = {row.data()};
    jpeg_write_scanlines(&info, rows, 1);
  }
}

}  // namespace

std::vector<unsigned char> encode_jpeg_444(const cv::Mat& image, int quality) {
  if (image.empty() || (image.type() != CV_8UC3 && image.type() != CV_8UC1)) {
    throw std::invalid_argument("encode_jpeg_444: expected a non-empty 8-bit BGR or grey image");
  }
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
    info.image_width = static_cast<JDIMENSION>(image.cols);
    info.image_height = static_cast<JDIMENSION>(image.rows);
    info.input_components = image.channels();
    info.in_color_space = image.channels() == 1 ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_set_defaults(&info);
    jpeg_set_quality(&info, quality, TRUE);
    for (int c = 0; c < info.num_components; ++c) info.comp_info[c].h_samp_factor = info.comp_info[c].v_samp_factor = 1;
    info.optimize_coding = TRUE;
    jpeg_start_compress(&info, TRUE);
    write_rows(info, image);
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

void write_jpeg_444(const cv::Mat& image, int quality, const std::filesystem::path& file, const std::string& what) {
  const std::vector<unsigned char> bytes = encode_jpeg_444(image, quality);
  std::ofstream out(file, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw OutputError(file.string(), what);  // "FILE: cannot write: WHAT"
}

}  // namespace hos
