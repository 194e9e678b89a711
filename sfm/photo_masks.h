// Masks of the user's photos (core/image_mask.h: black = not used): found,
// checked, staged beside the staged photos under the photos' staged names,
// turned and downscaled exactly as the photos are, and finally undistorted
// into the undistorted workspace as COLMAP's undistorter turns the photos.
//
// Where a photo's mask is found (COLMAP's naming: the photo's path relative
// to the photo folder plus ".png"):
//   - with sfm.masks = DIR: DIR/NAME.png for photo NAME ("DIR/DCIM/IMG_1.jpg.png");
//   - with sfm.masks = none: the PNG NAME.png beside photo NAME ("IMG_1.jpg.png" beside
//     "IMG_1.jpg"). Such a file is never taken for a photo (with or without
//     sfm.masks). No other name is matched ("IMG_1.png" is a photo).
// A mask is drawn over the photo's stored pixels (as COLMAP reads them) and
// turned with them; one photo turned a quarter by its EXIF orientation (5-8)
// may also have a mask of its upright size, taken as drawn upright. HEIC
// photos are decoded upright, so their masks are upright too. Video frames
// have no masks.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <set>
#include <string>

#include "core/sparse_model.h"

namespace hos::sfm {

// The folder the staged masks go to: staging_dir's sibling "masks"
// (WS/sfm/images -> WS/sfm/masks), each as <staged name>.png, which is what
// COLMAP's --ImageReader.mask_path expects. The caller clears it before
// staging (the sfm stage clears its workspace).
std::filesystem::path staged_mask_folder(const std::filesystem::path& staging_dir);

// True when file is "X.png" and X is among files (the photo folder's
// listing): the mask beside photo X, not a photo.
bool is_mask_beside_photo(const std::filesystem::path& file, const std::set<std::filesystem::path>& files);

// The mask of the photo at `relative` (its path under the photo folder, '/'
// separated): mask_folder/relative.png when mask_folder is given, else
// photo_folder/relative.png; nothing when that file does not exist.
std::optional<std::filesystem::path> find_mask(const std::filesystem::path& mask_folder,
                                               const std::filesystem::path& photo_folder,
                                               const std::string& relative);

// How a photo was turned into its staged copy.
struct PhotoTransform {
  int stored_width = 0;  // the decoded pixels, before the EXIF turn
  int stored_height = 0;
  int orientation = 1;  // EXIF orientation still applied when staging (1 = none)
  int staged_width = 0;
  int staged_height = 0;
};

// The mask of a photo's alpha channel (of its stored pixels, any depth):
// pixels at least half opaque are usable, the rest masked, as a renderer's
// transparent background is no surface. Empty when every pixel is usable.
cv::Mat mask_from_alpha(const cv::Mat& alpha);

// A mask of the photo's stored size given the photo's transform (the EXIF
// turn, then a nearest-neighbour resize to the staged size).
cv::Mat transform_mask(cv::Mat mask, const PhotoTransform& transform);

// Reads the mask file and gives it the photo's transform (the EXIF turn,
// then a nearest-neighbour resize to the staged size). Throws InputError
// naming the mask when it cannot be read or its size fits neither the
// stored nor (for orientations 5-8) the upright photo.
cv::Mat stage_mask(const std::filesystem::path& mask,
                   const std::filesystem::path& photo,
                   const PhotoTransform& transform);

// Writes the mask of every image of `undistorted` that has one in
// `masks` (NAME.png, the size of the image's camera in `distorted`), as
// COLMAP's image_undistorter warps the photos: each pixel of the PINHOLE
// image takes the value of the distorted pixel its ray meets (nearest, no
// blending); a pixel whose ray leaves the photo is masked. Images are
// matched by name. Returns the number of masks written. Throws InputError
// (a mask unreadable or of the wrong size), OutputError.
int undistort_masks(const SparseModel& distorted,
                    const SparseModel& undistorted,
                    const std::filesystem::path& masks,
                    const std::filesystem::path& out_folder);

}  // namespace hos::sfm
