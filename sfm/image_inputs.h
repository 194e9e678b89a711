// Checking the user's photo folder before COLMAP sees it, and staging the
// usable photos into the workspace (a link when a photo can be used as is, a
// re-encoded copy when it must be turned upright or downscaled).
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/reporter.h"
#include "sfm/exif.h"
#include "sfm/sfm_options.h"

namespace hos::sfm {

struct SkippedInput {
  std::filesystem::path file;
  std::string reason;
};

struct StagedImage {
  std::string name;              // file name inside the staging folder (= original name)
  std::filesystem::path source;  // the user's file
  int width = 0;                 // size as staged (upright, downscaled)
  int height = 0;
  std::optional<double> focal_length_mm;  // from EXIF
  std::optional<GpsPosition> gps;         // from EXIF (spatial matching, placement)
  std::string camera_make;                // from EXIF; empty when absent
  std::string camera_model;
  bool rewritten = false;  // re-encoded (rotated, downscaled or 16 to 8 bits) rather than linked
};

struct ImageInputs {
  std::vector<StagedImage> images;  // sorted by name
  std::vector<SkippedInput> skipped;
  // All photos share width, height and EXIF focal length: one camera fits.
  bool same_camera() const;
};

// File extensions COLMAP can read (lower case, with the dot).
const std::vector<std::string>& supported_image_extensions();

// Applies an EXIF orientation (1..8) so the image becomes upright.
cv::Mat apply_exif_orientation(const cv::Mat& image, int orientation);

// Width of the thumbnails prepare_images writes for the run report (px).
inline constexpr int kThumbnailWidth = 160;

// Checks every file at the top level of folder (hidden files are ignored),
// warns about each skipped one with the reason (an entry that cannot be
// read at all, such as a symlink loop, included), and stages the usable photos
// (converted to 8 bits per channel when deeper)
// into staging_dir (created). With a thumbnail_dir, also writes each usable
// photo, upright and kThumbnailWidth wide, as thumbnail_dir/NAME.jpg (the
// photo is decoded anyway, so this costs next to nothing). Throws InputError
// when the folder is missing or fewer than 3 usable photos remain, listing
// what was skipped.
ImageInputs prepare_images(const std::filesystem::path& folder,
                           const std::filesystem::path& staging_dir,
                           const SfmOptions& options,
                           Reporter& reporter,
                           const std::filesystem::path& thumbnail_dir = {});

}  // namespace hos::sfm
