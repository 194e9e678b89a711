// The per-vertex geometry one refinement round needs: one-rings (the
// umbrella Laplacian's stencil), area-weighted normals, face normals.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/types.h"

namespace hos::refine {

// The vertices sharing an edge with each vertex, CSR (neighbors of v are
// neighbors[offsets[v] .. offsets[v + 1]), sorted, no duplicates).
struct VertexRings {
  std::vector<int> offsets;
  std::vector<int> neighbors;

  int degree(int v) const { return offsets[v + 1] - offsets[v]; }
};

VertexRings vertex_rings(const TriangleMesh& mesh);

// Unnormalised face normals (length = twice the area).
std::vector<Eigen::Vector3f> face_area_normals(const TriangleMesh& mesh);

// Area-weighted unit vertex normals (zero for isolated or degenerate vertices).
std::vector<Eigen::Vector3f> vertex_normals(const TriangleMesh& mesh);

// Mean length of the faces' edges (each interior edge counted twice).
double mean_edge_length(const TriangleMesh& mesh);

}  // namespace hos::refine
