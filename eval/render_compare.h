// Texture quality by re-rendering: a textured mesh rendered (unlit) from the
// cameras of a COLMAP model and compared with that model's photos over the
// pixels the mesh covers.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/reporter.h"
#include "core/sparse_model.h"
#include "render/rasterizer.h"

namespace hos::eval {

struct ViewComparison {
  std::string name;
  std::size_t mask_pixels = 0;
  double psnr = 0.0;  // dB; +inf for identical pixels
  double ssim = 0.0;
};

struct RenderComparison {
  std::vector<ViewComparison> views;  // images with a photo and a non-empty mask, by image id
  std::size_t skipped_views = 0;      // the mesh covers no pixel of these
  double mean_psnr = 0.0;             // over views with finite PSNR
  double mean_ssim = 0.0;
};

// Photos are read from images_dir / image.name and must have the camera's
// size. Throws InputError naming a missing or unreadable photo. With a
// non-empty save_dir, each view is also written there as a PNG: the render
// beside the photo (for looking at what the figures measure), the render's
// alpha being its mask (see read_saved_render).
RenderComparison compare_renders(const render::RenderObject& object,
                                 const SparseModel& model,
                                 const std::filesystem::path& images_dir,
                                 Reporter& reporter,
                                 const std::filesystem::path& save_dir = {});

// One view saved by compare_renders: the render, its mask and the photo.
struct SavedRender {
  cv::Mat color, mask, photo;  // 8-bit BGR, 8-bit mask (255 = covered), 8-bit BGR
};

// Reads a PNG written by compare_renders; throws InputError naming the file
// when it is unreadable or not such an image (4 channels, even width).
SavedRender read_saved_render(const std::filesystem::path& path);

// A rectangle of the photo, in pixels.
struct PixelRect {
  int x = 0, y = 0, width = 0, height = 0;
};

// A rectangle of the photo and how much of the runs' error lies in it:
// where a run fails (an occlusion edge, a wrong patch of surface, a thin
// structure lost) shows as a few rectangles carrying a large part of its
// squared error.
struct ErrorRegion {
  PixelRect rect;  // tiles on the right and bottom edges are cut off there
  std::size_t common_pixels = 0;
  std::vector<double> mse;  // per run, 8-bit RGB, over the common pixels; empty if there are none
  double share = 0.0;       // of the first run's squared error over all common pixels
};

// Every run's render of one view against the photo over the pixels all runs
// cover. A run's PSNR over its own mask rewards trimming: surface that
// trimming removed is not measured, so a run with holes can score higher
// than one that covers more of the photo with an approximate surface. On
// the common pixels the runs are measured on the same part of the photo.
struct CommonComparison {
  std::size_t photo_pixels = 0;
  std::size_t common_pixels = 0;
  std::vector<std::size_t> covered_pixels;  // per run
  std::vector<double> psnr, ssim;           // per run, over the common pixels
  // Per run, after exposure_matched over the common pixels.
  std::vector<double> psnr_exposure_matched;
  std::vector<ErrorRegion> worst_tiles;  // CommonOptions::worst_tiles of them
  std::vector<ErrorRegion> regions;      // CommonOptions::regions, in their order
};

struct CommonOptions {
  int tile_size = 128;          // pixels
  std::size_t worst_tiles = 0;  // how many tiles to list, most of the first run's error first
  // Rectangles measured as the tiles are (a thin structure, a known
  // failure); each must lie inside the photo.
  std::vector<PixelRect> regions;
  // If set, each listed tile and region is also written as
  // crops_dir/tile_X_Y.png or crops_dir/region_X_Y_WxH.png: the photo beside
  // every run's render of it, pixels a run does not cover in magenta.
  std::filesystem::path crops_dir;
};

// Throws InputError when the views differ in size or their photos differ
// (they must be renders of the same view), or no pixel is common;
// ConfigError for a region outside the photo or crops with neither tiles
// nor regions; OutputError naming a crop or its folder that cannot be
// written.
CommonComparison compare_on_common_pixels(const std::vector<std::filesystem::path>& saved_views,
                                          const CommonOptions& options = {});

}  // namespace hos::eval
