// Charts: connected groups of edge-adjacent faces textured from the same view.
// Each chart becomes one rectangle of the atlas, so vertices on a chart's
// border are duplicated per chart.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/types.h"
#include "texture/mesh_topology.h"
#include "texture/visibility.h"

namespace hos::texture {

struct Chart {
  int view = -1;
  std::vector<int> faces;                    // face ids of the mesh
  std::vector<int> vertices;                 // mesh vertex ids, local order
  std::vector<Eigen::Vector3i> local_faces;  // corners as indices into vertices
};

// Merges small charts into a neighbour: a chart whose faces cover less than
// min_chart_area_px photo pixels in its view takes the view of the
// neighbouring chart it shares the most edges with, if that view is a
// candidate of every one of its faces (visible and photo-consistent) and
// sees them at no less than half the projected area (no blurrier texels).
// Smallest charts first, a few passes; labels -1 (unseen) are kept. Returns
// the number of charts merged away.
int merge_small_charts(const MeshTopology& topology,
                       const FaceViewCandidates& candidates,
                       double min_chart_area_px,
                       std::vector<int>& labels);

// Faces with label -1 (unseen) belong to no chart.
std::vector<Chart> build_charts(const TriangleMesh& mesh, const MeshTopology& topology, const std::vector<int>& labels);

}  // namespace hos::texture
