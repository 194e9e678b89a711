// Masks: which pixels of a photo may be used. COLMAP's convention: the mask
// of image NAME (a path relative to the image folder, "DCIM/IMG_1.jpg") is
// the PNG "NAME.png" under a mask folder ("DCIM/IMG_1.jpg.png"); black (0)
// pixels are masked out, any other value is usable. The undistorted
// workspace holds its images' masks, undistorted like the images, as
// <root>/masks/NAME.png (core/undistorted_workspace.h); mvs and texture use
// none of the masked pixels.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>

#include "core/undistorted_workspace.h"

namespace hos {

// Values of a mask as read_mask returns it.
inline constexpr unsigned char kMaskedOut = 0;
inline constexpr unsigned char kUsable = 255;

// folder/NAME.png.
std::filesystem::path mask_file(const std::filesystem::path& folder, const std::string& image_name);

// Reads a mask (PNG, JPEG, TIFF, ...; grey or colour, 8 or 16 bits) as
// CV_8U with kMaskedOut where the file is black and kUsable elsewhere.
// Throws InputError naming the file when it cannot be read.
cv::Mat read_mask(const std::filesystem::path& file);

// read_mask, and the mask must be width x height pixels: InputError naming
// the mask, both sizes and image_path (the photo it belongs to) otherwise.
cv::Mat read_mask(const std::filesystem::path& file, int width, int height, const std::string& image_path);

// Writes a mask (CV_8U, kMaskedOut / kUsable) as PNG, creating its folder.
// Throws OutputError.
void write_mask(const cv::Mat& mask, const std::filesystem::path& file);

// <root>/masks.
std::filesystem::path workspace_mask_folder(const UndistortedWorkspace& workspace);

// The mask of a registered image of the workspace, checked against its
// camera's size; an empty Mat when the workspace has no mask for it (every
// pixel usable). Throws InputError as read_mask.
cv::Mat load_workspace_mask(const UndistortedWorkspace& workspace, const ImageRecord& image);

// The masked region grown by one pixel, so that no bilinear sample taken
// at a usable pixel reaches a masked one (an empty mask stays empty).
cv::Mat grow_masked_region(const cv::Mat& mask);

// Masked-out pixels of a mask (0 for an empty one).
std::size_t count_masked(const cv::Mat& mask);

}  // namespace hos
