#include "core/image_mask.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/reporter.h"

namespace hos {
namespace fs = std::filesystem;

fs::path mask_file(const fs::path& folder, const std::string& image_name) { return folder / (image_name + ".png"); }

cv::Mat read_mask(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) throw InputError(file.string(), "mask file is missing or not a file");
  cv::Mat grey;
  try {
    // Any depth: a 16-bit mask's small values are not black.
    grey = cv::imread(file.string(), cv::IMREAD_GRAYSCALE | cv::IMREAD_ANYDEPTH | cv::IMREAD_IGNORE_ORIENTATION);
  } catch (const cv::Exception&) {
    grey.release();
  }
  if (grey.empty()) throw InputError(file.string(), "cannot be read as a mask image (expected PNG, black = masked)");
  cv::Mat mask = grey > 0;  // kUsable where not black
  return mask;
}

cv::Mat read_mask(const fs::path& file, int width, int height, const std::string& image_path) {
  cv::Mat mask = read_mask(file);
  if (mask.cols != width || mask.rows != height) {
    throw InputError(file.string(), format_message("mask is ", mask.cols, "x", mask.rows, " pixels but its photo ",
                                                   image_path, " is ", width, "x", height));
  }
  return mask;
}

void write_mask(const cv::Mat& mask, const fs::path& file) {
  std::error_code ec;
  fs::create_directories(file.parent_path(), ec);
  bool written = false;
  try {
    written = cv::imwrite(file.string(), mask);
  } catch (const cv::Exception&) {
    written = false;
  }
  if (!written) throw OutputError(file.string(), "the mask");
}

fs::path workspace_mask_folder(const UndistortedWorkspace& workspace) { return workspace.root / "masks"; }

cv::Mat load_workspace_mask(const UndistortedWorkspace& workspace, const ImageRecord& image) {
  const fs::path file = mask_file(workspace_mask_folder(workspace), image.name);
  std::error_code ec;
  if (!fs::exists(file, ec)) return {};
  const Camera& camera = workspace.model.camera_of(image);
  return read_mask(file, camera.width, camera.height, workspace.image_path(image).string());
}

cv::Mat grow_masked_region(const cv::Mat& mask) {
  if (mask.empty()) return mask;
  cv::Mat grown;
  cv::erode(mask, grown, cv::Mat::ones(3, 3, CV_8U), cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
  return grown;
}

std::size_t count_masked(const cv::Mat& mask) {
  if (mask.empty()) return 0;
  return mask.total() - static_cast<std::size_t>(cv::countNonZero(mask));
}

}  // namespace hos
