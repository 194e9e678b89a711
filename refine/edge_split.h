// Mesh refinement in resolution: edges longer than a per-vertex limit are
// split at their midpoints, red-green, so the surface does not move, the mesh
// stays manifold and no face is left with a hanging vertex. The refinement
// subdivides the recon mesh until its edges are a few pixels long in the
// photos (refine.edge_pixels), so it can carry the detail they show.
#pragma once

#include <cstddef>
#include <vector>

#include "core/types.h"

namespace hos::refine {

struct EdgeSplitResult {
  TriangleMesh mesh;
  int split_edges = 0;
  bool budget_reached = false;  // more edges were too long than max_faces allowed to split
};

// Splits every edge (a, b) with |a - b| > min(limit[a], limit[b]); when that
// would give more than max_faces faces, the edges furthest above their limit
// (by ratio) come first and the result has at most max_faces faces (or the
// input's count, if larger). A face with two or three split edges becomes four
// faces, one with a single split edge two. New vertices take the mean of
// their edge's normals (renormalised), colours and scalars. limit has one
// entry per vertex; +inf never splits.
EdgeSplitResult split_long_edges(const TriangleMesh& mesh, const std::vector<float>& limit, std::size_t max_faces);

}  // namespace hos::refine
