// Grid and mesh topology helpers of the recon tests (the sampled shapes are
// synth/shapes.h).
#pragma once

#include <functional>
#include <random>

#include "core/types.h"
#include "recon/grid.h"
#include "synth/shapes.h"

namespace hos::recon::testing {

// A grid of n^3 nodes with spacing h at the origin.
GridGeometry cube_grid(int n, double h);

struct MeshTopology {
  std::size_t vertices = 0, edges = 0, faces = 0;
  std::size_t boundary_edges = 0;     // used by one face
  std::size_t nonmanifold_edges = 0;  // used by more than two faces
  std::size_t misoriented_edges = 0;  // interior edges traversed the same way twice
  int components = 0;
  long euler() const { return long(vertices) - long(edges) + long(faces); }
  bool watertight() const { return boundary_edges == 0 && nonmanifold_edges == 0; }
};
MeshTopology analyze_topology(const TriangleMesh& mesh);

// Signed volume (positive when faces are counter-clockwise seen from outside).
double signed_volume(const TriangleMesh& mesh);

}  // namespace hos::recon::testing
