// Which vertices a round searches, and targets for the others: a target
// measures the surface's offset averaged over a patch many vertices wide
// (docs/refine.md), so neighbouring vertices' searches largely repeat each
// other, most of all at the coarse levels, where a patch covers hundreds of
// vertices. Vertices a few pixels apart are searched; the rest take the
// targets of the nearest searched ones.
#pragma once

#include <vector>

#include "core/types.h"
#include "refine/mesh_geometry.h"
#include "refine/photo_consistency.h"

namespace hos::refine {

// Greedy in vertex order: a vertex is searched unless it lies within the
// radius of an already searched vertex v (|x - x_v| < radius[v], reached
// through edges of vertices that all do). Deterministic; radius 0 (or below
// every edge length) searches every vertex. Returns the searched vertices in
// increasing order.
std::vector<int> spaced_vertices(const TriangleMesh& mesh, const VertexRings& rings, const std::vector<float>& radius);

// Targets for the vertices not searched, ring by ring out from the searched
// ones: each takes, from its neighbours that have one, the mean weight and
// the weight-averaged offset (score 0: it was not measured). Vertices no
// searched vertex reaches keep no target.
void fill_targets(const VertexRings& rings, const std::vector<char>& searched, std::vector<VertexTarget>& targets);

}  // namespace hos::refine
