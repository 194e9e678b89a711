// The mvs stage: undistorted workspace in, dense oriented points out.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/reporter.h"
#include "core/types.h"
#include "core/undistorted_workspace.h"
#include "mvs/mvs_options.h"

namespace hos::mvs {

struct MvsViewStats {
  std::string name;
  int num_sources = 0;
  std::size_t pixels = 0;        // of the depth map (finest level)
  std::size_t valid_pixels = 0;  // with a depth
  std::size_t textureless_pixels = 0;
  double seconds = 0.0;
  bool skipped = false;
};

struct MvsStats {
  int views = 0;
  int views_skipped = 0;
  std::size_t points = 0;
  double seconds_depth = 0.0, seconds_fusion = 0.0;
  double megapixels_per_view = 0.0;  // at the matching scale
  std::vector<MvsViewStats> per_view;
};

struct MvsResult {
  PointCloud points;  // x y z, normals towards the cameras, colours, confidence
  MvsStats stats;
};

// Runs PatchMatch on every registered image and fuses the depth maps. If
// depth_map_folder is not empty, every depth map is also written there as
// <image name>.depth.tiff (CV_32F) and .normal.tiff for inspection.
// Throws ConfigError, InputError (unreadable images), StageError (no view
// could be matched), Cancelled.
MvsResult run_mvs(const UndistortedWorkspace& workspace,
                  const MvsOptions& options,
                  Reporter& reporter,
                  const std::filesystem::path& depth_map_folder = {});

}  // namespace hos::mvs
