// Charts: connected groups of edge-adjacent faces textured from the same view.
// Each chart becomes one rectangle of the atlas, so vertices on a chart's
// border are duplicated per chart.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/types.h"
#include "texture/mesh_topology.h"

namespace hos::texture {

struct Chart {
  int view = -1;
  std::vector<int> faces;                    // face ids of the mesh
  std::vector<int> vertices;                 // mesh vertex ids, local order
  std::vector<Eigen::Vector3i> local_faces;  // corners as indices into vertices
};

// Faces with label -1 (unseen) belong to no chart.
std::vector<Chart> build_charts(const TriangleMesh& mesh, const MeshTopology& topology, const std::vector<int>& labels);

}  // namespace hos::texture
