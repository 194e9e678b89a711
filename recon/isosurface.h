// Isosurface extraction (paper sec. 4.4). The paper adapts Lewiner's marching
// cubes; hos splits every cube into the six tetrahedra of the Freudenthal
// (Kuhn) triangulation around its main diagonal instead. Linear interpolation
// in a tetrahedron is unambiguous and neighbouring cubes split their shared
// faces the same way, so the surface is watertight and 2-manifold by
// construction, without the ambiguity tables of marching cubes; the price is
// about twice as many triangles.
#pragma once

#include "core/types.h"
#include "recon/grid.h"

namespace hos::recon {

// Extracts {f = isovalue} with faces counter-clockwise seen from the side
// where f > isovalue (outside, since f increases outward). The ghost ring
// around the grid (value 0) is included, so the surface closes at the domain
// boundary when 0 is above the isovalue.
TriangleMesh extract_isosurface(const ScalarGrid& f, double isovalue);

// Area-weighted vertex normals from the faces.
void compute_vertex_normals(TriangleMesh& mesh);

}  // namespace hos::recon
