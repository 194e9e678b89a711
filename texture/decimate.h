// Optional decimation to a face budget before texturing, with quadric error
// metrics (meshoptimizer's meshopt_simplify, which keeps the mesh boundary
// in place).
#pragma once

#include "core/types.h"

namespace hos::texture {

struct DecimationStats {
  std::size_t faces_before = 0;
  std::size_t faces_after = 0;
  float relative_error = 0.0f;  // meshoptimizer's error, relative to the mesh extent
};

// Returns the mesh unchanged if it has at most max_faces faces. Vertex
// colours and normals are carried over for the vertices that remain.
TriangleMesh decimate_mesh(const TriangleMesh& mesh, std::size_t max_faces, DecimationStats* stats = nullptr);

}  // namespace hos::texture
