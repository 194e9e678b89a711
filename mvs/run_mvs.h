// The mvs stage: undistorted workspace in, dense oriented points out.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/reporter.h"
#include "core/types.h"
#include "core/undistorted_workspace.h"
#include "core/view_range.h"
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

// Split runs (job arrays on a cluster): the views are the model's registered
// images in the order of their ids, numbered from 0 (core/view_range.h).

// Number of views run_mvs would match (the model's registered images).
int count_views(const UndistortedWorkspace& workspace);

// The depth maps of the views in `range` only, each written atomically into
// folder as <image name>.dmap (what fuse_depth_map_folder reads) beside the
// .tiff maps run_mvs writes. The finer levels of a view need the coarse maps
// of its sources, which are recomputed here; every map equals the one of a
// whole run bit for bit (PatchMatch's random numbers depend on the pixel and
// the iteration only). Returns the per-view figures of the range. Throws as
// run_mvs, except that no fusion happens.
MvsStats compute_depth_maps(const UndistortedWorkspace& workspace,
                            const MvsOptions& options,
                            Reporter& reporter,
                            const ViewRange& range,
                            const std::filesystem::path& folder);

// Fuses the depth maps compute_depth_maps wrote into folder (every view that
// is not skipped must have one) into the points run_mvs returns: the same
// points, byte for byte. Throws InputError naming a missing or damaged map,
// StageError as run_mvs.
MvsResult fuse_depth_map_folder(const UndistortedWorkspace& workspace,
                                const MvsOptions& options,
                                Reporter& reporter,
                                const std::filesystem::path& folder);

}  // namespace hos::mvs
