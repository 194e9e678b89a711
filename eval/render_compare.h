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
// beside the photo (for looking at what the figures measure).
RenderComparison compare_renders(const render::RenderObject& object,
                                 const SparseModel& model,
                                 const std::filesystem::path& images_dir,
                                 Reporter& reporter,
                                 const std::filesystem::path& save_dir = {});

}  // namespace hos::eval
