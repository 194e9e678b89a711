// The texture stage's library entry point: mesh + posed photos -> textured
// mesh (geometry with UVs, atlases, root transform) and figures.
//
// Steps: decimate (optional) -> visibility (depth buffers) -> exposure gains
// (optional) -> photo-consistency outlier rejection -> view selection (graph
// cuts) -> charts -> seam leveling -> atlas packing and filling; faces no
// view sees get the colour of their neighbours (reported).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/histogram.h"
#include "core/reporter.h"
#include "core/types.h"
#include "core/undistorted_workspace.h"
#include "core/view_range.h"
#include "texture/placement.h"
#include "texture/texture_options.h"
#include "texture/texture_view.h"
#include "texture/textured_mesh.h"

namespace hos::texture {

inline constexpr int kMaxPlottedViewsPerFace = 30;

struct TextureStats {
  std::size_t input_faces = 0;
  std::size_t faces = 0;  // after decimation
  int num_views = 0;
  std::int64_t num_candidates = 0;          // (face, view) pairs that pass visibility
  std::int64_t num_outlier_rejections = 0;  // pairs removed by the photo-consistency check
  int num_unseen_faces = 0;                 // coloured from neighbours
  int num_charts = 0;
  int num_merged_charts = 0;  // small charts that took a neighbour's view
  int num_atlases = 0;
  std::vector<std::pair<int, int>> atlas_sizes;  // width, height
  double texel_scale = 1.0;
  double atlas_coverage = 0.0;  // share of atlas texels inside textured triangles
  int num_seam_vertices = 0;
  double mean_seam_jump_before = 0.0;  // 8-bit RGB distance at seam vertices
  double mean_seam_jump_after = 0.0;
  Histogram seam_jumps_before, seam_jumps_after;  // per pair of chart copies (seam_leveling.h)
  // Faces by the number of photos that see them (after the visibility test),
  // one bin per count from 0 to kMaxPlottedViewsPerFace (more in the last bin).
  Histogram views_per_face;
  std::vector<Eigen::Vector3f> exposure_gains;              // RGB gain per view, in workspace image order
  Eigen::Vector3d estimated_up = Eigen::Vector3d::UnitY();  // model frame
  // Wall time of each step in seconds, in order.
  std::vector<std::pair<std::string, double>> step_seconds;
};

struct TextureResult {
  TexturedMesh mesh;
  TextureStats stats;
  // The root matrix's making (texture/placement.h); identity with up_axis none.
  Placement placement;
};

// placement: the photos' GPS or a measured distance, for the root matrix.
TextureResult texture_mesh(const TriangleMesh& mesh,
                           const std::vector<TextureView>& views,
                           const TextureOptions& options,
                           Reporter& reporter,
                           const PlacementInput& placement = {});

// Loads the workspace's photos and textures the mesh.
TextureResult texture_mesh(const TriangleMesh& mesh,
                           const UndistortedWorkspace& workspace,
                           const TextureOptions& options,
                           Reporter& reporter,
                           const PlacementInput& placement = {});

// Split runs (job arrays on a cluster, docs/scale.md): the views are the
// workspace's registered images in the order of their ids, numbered from 0
// (core/view_range.h).
//
// The per-view work of the views in `range` (the visibility test and each
// visible face's samples, texture/visibility.h), each view's result written
// atomically into folder (texture/view_data.h). The mesh is checked and
// decimated as texture_mesh does. Returns the number of views computed (0
// for a range past the last view). Throws as texture_mesh.
int compute_view_data(const TriangleMesh& mesh,
                      const UndistortedWorkspace& workspace,
                      const TextureOptions& options,
                      Reporter& reporter,
                      const ViewRange& range,
                      const std::filesystem::path& folder);

// texture_mesh from the view data compute_view_data wrote into folder for
// every view: the same result, byte for byte. Throws InputError naming a
// missing, truncated or foreign view data file, otherwise as texture_mesh.
TextureResult texture_mesh_from_view_data(const TriangleMesh& mesh,
                                          const UndistortedWorkspace& workspace,
                                          const TextureOptions& options,
                                          Reporter& reporter,
                                          const std::filesystem::path& folder,
                                          const PlacementInput& placement = {});

}  // namespace hos::texture
