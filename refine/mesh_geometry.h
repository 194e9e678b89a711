// The per-vertex geometry one refinement round needs: one-rings (the
// umbrella Laplacian's stencil: VertexRings of core/mesh_connectivity.h),
// area-weighted normals, face normals.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/mesh_connectivity.h"
#include "core/types.h"

namespace hos::refine {

// Unnormalised face normals (length = twice the area).
std::vector<Eigen::Vector3f> face_area_normals(const TriangleMesh& mesh);

// Area-weighted unit vertex normals (zero for isolated or degenerate vertices).
std::vector<Eigen::Vector3f> vertex_normals(const TriangleMesh& mesh);

// Mean length of the faces' edges (each interior edge counted twice).
double mean_edge_length(const TriangleMesh& mesh);

}  // namespace hos::refine
