// Checking the user's photo folder before COLMAP sees it, and staging the
// usable photos into the workspace (a link when a photo can be used as is, a
// copy carrying the photo's EXIF when it must be turned upright, downscaled,
// converted to 8 bits or from HEIC, or given a GPS altitude).
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/reporter.h"
#include "sfm/exif.h"
#include "sfm/sfm_options.h"
#include "sfm/video_frames.h"

namespace hos::sfm {

struct SkippedInput {
  std::filesystem::path file;
  std::string reason;
};

struct StagedImage {
  // Name inside the staging folder and COLMAP's image name: the path
  // relative to the photo folder with '/' ("DCIM/100APPLE/IMG_1.jpg"), plus
  // ".jpg" for a HEIC staged as JPEG ("IMG_2.HEIC.jpg").
  std::string name;
  std::filesystem::path source;  // the user's file
  int width = 0;                 // size as staged (upright, downscaled)
  int height = 0;
  std::optional<double> focal_length_mm;  // from EXIF
  std::optional<GpsPosition> gps;         // from EXIF (spatial matching, placement)
  // GPS with latitude and longitude but no altitude (gps->altitude_m empty):
  // the staged copy carries altitude 0 so that COLMAP takes the position;
  // its height means nothing.
  bool gps_altitude_missing = false;
  std::string camera_make;  // from EXIF; empty when absent
  std::string camera_model;
  bool rewritten = false;  // re-encoded (rotated, downscaled, 16 to 8 bits, HEIC) rather than linked or copied
  // Staged name of the video clip this is a frame of (sfm/video_frames.h);
  // empty for a photo. The frames of one clip share one camera.
  std::string video_clip;
  // A mask was staged for it (sfm/photo_masks.h) as
  // staged_mask_folder(staging_dir)/NAME.png.
  bool masked = false;
  // That mask is the photo's alpha channel (no mask file was given for it).
  bool masked_by_alpha = false;
};

struct ImageInputs {
  std::vector<StagedImage> images;  // sorted by name
  std::vector<SkippedInput> skipped;
  std::vector<VideoClipSummary> videos;  // the clips whose frames are among images
  // The staged masks (staged_mask_folder), empty when no photo has one.
  std::filesystem::path mask_folder;
  int masked_photos() const;
  // All photos share width, height and EXIF focal length: one camera fits.
  bool same_camera() const;
};

// Applies an EXIF orientation (1..8) so the image becomes upright.
cv::Mat apply_exif_orientation(const cv::Mat& image, int orientation);

// Width of the thumbnails prepare_images writes for the run report (px).
inline constexpr int kThumbnailWidth = 160;

// Writes the upright photo kThumbnailWidth wide as a small JPEG.
void write_thumbnail(const cv::Mat& image, const std::filesystem::path& file);

// True for a folder holding a hos workspace: a pipeline workspace (run.json)
// or an sfm stage's (sfm/report.json or sfm/database.db). The photo search
// never enters one, so a workspace inside the photo folder is not taken for
// photos.
bool is_hos_workspace(const std::filesystem::path& folder);

// Every file under folder, recursively, sorted by path: the entries the
// photo check looks at. Hidden files and folders (name starting with '.'),
// hos workspaces and the folders in `excluded` are left out; so are
// symbolic links to folders. An entry that cannot be examined (a symlink
// loop) is listed, to be skipped with its reason. A missing folder gives an
// empty list.
std::vector<std::filesystem::path> list_input_files(const std::filesystem::path& folder,
                                                    const std::vector<std::filesystem::path>& excluded = {});

// The files of list_input_files whose content is a photo (by its first
// bytes) or a video clip: what the sfm stage reads, for the pipeline's
// resume fingerprint. Sidecars (.xmp, .aae), notes and the like are not.
// A file given instead of a folder (a video clip) is the list.
std::vector<std::filesystem::path> list_photo_files(const std::filesystem::path& folder,
                                                    const std::vector<std::filesystem::path>& excluded = {});

// Checks every file of list_input_files(folder, excluded + the staging and
// thumbnail folders), recognising JPEG, PNG, TIFF, BMP and HEIC/HEIF by
// content, warns about each skipped one with the reason (an entry that
// cannot be read at all, such as a symlink loop, included), and stages the
// usable photos into staging_dir (created), each under its relative name
// (StagedImage::name). A staged copy carries the photo's EXIF. A photo's
// mask (sfm/photo_masks.h: options.masks, or NAME.png beside it) is staged
// with the photo's turn and size into staged_mask_folder(staging_dir); a
// mask that cannot be read or does not fit its photo is an InputError
// naming it. With a
// thumbnail_dir, also writes each usable photo, upright and kThumbnailWidth
// wide, as thumbnail_dir/NAME.jpg (the photo is decoded anyway, so this
// costs next to nothing). Throws InputError when the folder is missing or
// fewer than 3 usable photos remain, listing what was skipped.
ImageInputs prepare_images(const std::filesystem::path& folder,
                           const std::filesystem::path& staging_dir,
                           const SfmOptions& options,
                           Reporter& reporter,
                           const std::filesystem::path& thumbnail_dir = {},
                           const std::vector<std::filesystem::path>& excluded = {});

}  // namespace hos::sfm
