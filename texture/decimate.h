// Decimation with quadric error metrics (meshoptimizer's meshopt_simplify,
// which keeps the mesh boundary in place): of the mesh before texturing
// (where the surface moves by a fraction of a photo pixel, or to a face
// budget), and of a textured model into its preview (a level of detail
// light enough for a web page).
#pragma once

#include <vector>

#include "core/camera.h"
#include "core/sparse_model.h"
#include "core/types.h"
#include "texture/texture_view.h"
#include "texture/textured_mesh.h"

namespace hos::texture {

struct DecimationStats {
  std::size_t faces_before = 0;
  std::size_t faces_after = 0;
  float relative_error = 0.0f;  // meshoptimizer's error, relative to the mesh extent
};

// What the error bound needs of a registered photo: its pinhole camera and
// pose (keypoints dropped).
struct SamplingCamera {
  Camera camera;
  ImageRecord pose;
};
std::vector<SamplingCamera> sampling_cameras(const std::vector<TextureView>& views);
std::vector<SamplingCamera> sampling_cameras(const SparseModel& model);

// The size of a photo pixel on the surface where the photos sample it most
// finely (scene units): at each vertex the smallest depth / focal length
// over the photos it lies in front of and inside the frame of, and of these
// the given quantile over the vertices (at most 200000 of them, evenly
// spaced). A global bound, so the quantile is low: the closest parts decide.
// 0 when no vertex lies in a photo.
double finest_pixel_size(const TriangleMesh& mesh, const std::vector<SamplingCamera>& cameras, double quantile = 0.05);

// At most max_faces faces (0 = no budget) and, where max_error > 0, only the
// collapses whose quadric error is at most max_error (scene units). Returns
// the mesh unchanged when neither asks for anything. Vertex colours and
// normals are carried over for the vertices that remain.
TriangleMesh decimate_mesh(const TriangleMesh& mesh,
                           std::size_t max_faces,
                           double max_error,
                           DecimationStats* stats = nullptr);

// The textured model on one atlas page of at most max_atlas_size texels per
// side (the pages tiled into a grid, scaled down with area averaging, UVs
// moved along) with at most max_faces faces. The simplifier sees the copies
// of a vertex on chart seams as one (same position), so collapses keep
// every triangle inside its chart and every kept vertex keeps its UV.
// Root matrix and placement are the model's.
TexturedMesh preview_model(const TexturedMesh& mesh,
                           std::size_t max_faces,
                           int max_atlas_size,
                           DecimationStats* stats = nullptr);

}  // namespace hos::texture
