// Baseline JPEG with full chroma resolution (4:4:4) and optimized Huffman
// tables, through libjpeg: OpenCV's encoder halves the chroma (4:2:0), which
// blurs colour edges of every copy hos writes (atlases, turned photos).
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace hos {

// Encodes a CV_8UC3 (BGR) or CV_8UC1 image at quality 1-100. Throws
// std::invalid_argument for another type or an empty image and
// std::runtime_error when libjpeg fails.
std::vector<unsigned char> encode_jpeg_444(const cv::Mat& image, int quality);

// encode_jpeg_444 into file (not atomically: for staged copies whose folder
// is replaced as a whole). Throws OutputError naming the file and `what`
// ("the video frame") when it cannot be written.
void write_jpeg_444(const cv::Mat& image, int quality, const std::filesystem::path& file, const std::string& what);

}  // namespace hos
