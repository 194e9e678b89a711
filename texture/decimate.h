// Decimation with quadric error metrics (meshoptimizer's meshopt_simplify,
// which keeps the mesh boundary in place): optionally of the mesh before
// texturing, and of a textured model into its preview (a level of detail
// light enough for a web page).
#pragma once

#include "core/types.h"
#include "texture/textured_mesh.h"

namespace hos::texture {

struct DecimationStats {
  std::size_t faces_before = 0;
  std::size_t faces_after = 0;
  float relative_error = 0.0f;  // meshoptimizer's error, relative to the mesh extent
};

// Returns the mesh unchanged if it has at most max_faces faces. Vertex
// colours and normals are carried over for the vertices that remain.
TriangleMesh decimate_mesh(const TriangleMesh& mesh, std::size_t max_faces, DecimationStats* stats = nullptr);

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
