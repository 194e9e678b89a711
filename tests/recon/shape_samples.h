// Analytic shapes sampled with noise, and mesh topology checks, shared by the
// recon tests.
#pragma once

#include <functional>
#include <random>

#include "core/types.h"
#include "recon/grid.h"

namespace hos::recon::testing {

// A grid of n^3 nodes with spacing h at the origin.
GridGeometry cube_grid(int n, double h);

// n points on the unit-speed parametrised surfaces below, with Gaussian noise
// of standard deviation noise along the normal; exact outward normals.
PointCloud sample_sphere(int n, double radius, double noise, unsigned seed);
PointCloud sample_torus(int n, double major, double minor, double noise, unsigned seed);
// Box [-a, a]^3 with edges rounded by radius r (a > r).
PointCloud sample_rounded_box(int n, double a, double r, double noise, unsigned seed);
// Square patch [-s, s]^2 in the plane z = 0, normals +z.
PointCloud sample_plane_patch(int n, double s, double noise, unsigned seed);

// Replaces every normal by the closest of the 6 axis directions: the sphere
// "scanned from 6 directions" with one orientation per scan.
void coarsen_to_axis_directions(PointCloud& points);

struct MeshTopology {
  std::size_t vertices = 0, edges = 0, faces = 0;
  std::size_t boundary_edges = 0;      // used by one face
  std::size_t nonmanifold_edges = 0;   // used by more than two faces
  std::size_t misoriented_edges = 0;   // interior edges traversed the same way twice
  int components = 0;
  long euler() const { return long(vertices) - long(edges) + long(faces); }
  bool watertight() const { return boundary_edges == 0 && nonmanifold_edges == 0; }
};
MeshTopology analyze_topology(const TriangleMesh& mesh);

// Signed volume (positive when faces are counter-clockwise seen from outside).
double signed_volume(const TriangleMesh& mesh);

}  // namespace hos::recon::testing
