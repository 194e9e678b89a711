#include "pipeline/run_bounds.h"

#include <algorithm>
#include <opencv2/imgcodecs.hpp>

#include "sfm/sfm_options.h"

namespace hos::pipeline {
namespace fs = std::filesystem;

double megapixels_at(int size) { return 0.75 * double(size) * size / 1e6; }

RunBounds run_bounds(const fs::path& photos, const PipelineConfig& config) {
  RunBounds bounds;
  int files = 0;
  std::uintmax_t largest_size = 0;
  fs::path largest;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(photos, ec)) {
    if (!entry.is_regular_file(ec) || entry.path().filename().string().rfind('.', 0) == 0) continue;
    ++files;
    const std::uintmax_t size = entry.file_size(ec);
    if (!ec && size > largest_size) {
      largest_size = size;
      largest = entry.path();
    }
  }
  bounds.views = std::max(files, 1);
  if (!largest.empty()) {
    // Decoded at 1/8 (JPEG decodes only the DCT's low frequencies); each
    // pixel stands for up to 8x8 of the photo.
    const cv::Mat reduced = cv::imread(largest.string(), cv::IMREAD_REDUCED_GRAYSCALE_8);
    if (!reduced.empty()) bounds.photo_megapixels = 64.0 * reduced.total() / 1e6;
  }
  const auto* sfm = stage_options<sfm::SfmOptions>(config, "sfm");
  if (sfm && sfm->max_image_size > 0) {
    const double cap = megapixels_at(sfm->max_image_size);
    bounds.photo_megapixels = bounds.photo_megapixels > 0 ? std::min(bounds.photo_megapixels, cap) : cap;
  }
  return bounds;
}

}  // namespace hos::pipeline
