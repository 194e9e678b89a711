// Connectivity of a triangle mesh used by view selection, leveling and atlas.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "core/types.h"

namespace hos::texture {

struct MeshTopology {
  // Faces sharing edge c (vertices c, c+1) of face f, or -1 on a boundary.
  // Non-manifold edges link their faces pairwise in index order.
  std::vector<std::array<int, 3>> face_neighbors;
  std::vector<Eigen::Vector3f> face_normals;  // unit (zero for degenerate faces)
  std::vector<float> face_areas;
  std::vector<Eigen::Vector3f> vertex_normals;  // area-weighted, unit
  // Faces around each vertex, CSR.
  std::vector<int> vertex_face_offsets;
  std::vector<int> vertex_faces;
};

MeshTopology build_topology(const TriangleMesh& mesh);

}  // namespace hos::texture
