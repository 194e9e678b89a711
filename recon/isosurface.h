// Isosurface extraction (paper sec. 4.4): marching cubes with the topology of
// the trilinear interpolant, after Lewiner et al.'s case handling, derived
// per cell rather than read from hand-written case tables:
// - one vertex per grid edge whose ends lie on different sides of the
//   isovalue, shared by the four cells around that edge;
// - on each cube face the crossings are joined into segments; a face with
//   four crossings is resolved by the asymptotic decider (the bilinear
//   saddle value against the isovalue), which both cells sharing the face
//   evaluate on the same numbers, so they agree;
// - the segments chain into closed loops, each triangulated with the
//   diagonals that maximise the smallest triangle quality, never one between
//   two crossings on a cube face (the neighbour could pick it too); loops
//   that cannot avoid one are fanned around a vertex added inside the cell;
// - where the trilinear interpolant joins two loops through the cell
//   interior (a tunnel, found by sweeping the cell in slices), the two loops
//   are stitched into a tube instead of two disks.
// The result has no non-manifold edges, faces oriented consistently, and is
// watertight wherever the isosurface is closed.
#pragma once

#include "core/types.h"
#include "recon/active_nodes.h"
#include "recon/grid.h"

namespace hos::recon {

// Extracts {f = isovalue} with faces counter-clockwise seen from the side
// where f > isovalue (outside, since f increases outward). The ghost ring
// around the grid (value 0) is included, so the surface closes at the domain
// boundary when 0 is above the isovalue. Vertex normals are the gradient of f
// (central differences at the nodes, interpolated along the edge), pointing
// outward.
TriangleMesh extract_isosurface(const ScalarGrid& f, double isovalue);

// The isosurface of a function stored on a band: only the cells whose eight
// corners are active are meshed (their faces are those of the whole grid's
// isosurface there), the rest left open; vertices no face uses are dropped.
// On a layout of every node, the same as above.
TriangleMesh extract_isosurface(const GridGeometry& g, const StoredField& f, double isovalue);

// The grid edge an isosurface vertex lies on: from `node` to its neighbour
// along +axis; axis -1 for a vertex added inside a cell.
struct GridEdge {
  Eigen::Vector3i node = Eigen::Vector3i::Zero();
  int axis = -1;
};

// The same, and for every vertex its grid edge (vertex_edges, #V): meshes
// extracted from adjacent sub-grids of one lattice are joined by them
// (tiled_reconstruction.h), since positions computed from two sub-grids'
// origins may differ in the last bit.
TriangleMesh extract_isosurface(const GridGeometry& g,
                                const StoredField& f,
                                double isovalue,
                                std::vector<GridEdge>& vertex_edges);

}  // namespace hos::recon
