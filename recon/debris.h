// Debris: small surface pieces detached from the main surface. Isolated
// clusters of outlier points and fragments the trimming cuts off become
// closed blobs or shreds floating around the model; mesh cleaning removes
// them (OpenMVS's Mesh::Clean drops spurious components, Meshroom's
// MeshFiltering keeps large components), and so does this step.
#pragma once

#include <cstddef>
#include <vector>

#include "core/types.h"
#include "recon/recon_options.h"

namespace hos::recon {

struct DebrisReport {
  std::size_t components = 0;  // connected pieces before the removal
  std::size_t components_removed = 0;
  std::size_t faces_removed = 0;
  double area_removed = 0.0;  // in the mesh's units, squared
  double area_kept = 0.0;
};

// Removes the pieces (connected_pieces of core/mesh_connectivity.h: faces
// sharing a vertex, so a thin part attached to the surface belongs to it)
// whose area is below options.min_area_fraction of the
// largest piece's, then the vertices no face uses. With options.remove off
// only counts the pieces and their area.
DebrisReport remove_debris(TriangleMesh& mesh, const DebrisOptions& options);

}  // namespace hos::recon
