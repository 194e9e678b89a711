// Whether a mesh passes through itself: pairs of faces that share no vertex
// and cross (an edge of one pierces the other). Used to check that the
// refinement, which moves vertices, adds no self-intersections.
#pragma once

#include <cstddef>

#include "core/types.h"

namespace hos::eval {

// The number of crossing face pairs. Faces that share a vertex are not
// tested (their contact is the shared vertex or edge), nor are coplanar
// overlaps. A uniform grid over the faces' bounding boxes keeps this near
// linear in the face count.
std::size_t count_self_intersections(const TriangleMesh& mesh);

}  // namespace hos::eval
