// Analytic shapes shared by the synthetic scenes, the tests and the
// benchmarks: a subdivided icosahedron, and point samples of primitives with
// exact normals.
#pragma once

#include <Eigen/Core>
#include <functional>

#include "core/types.h"

namespace hos::synth {

// Icosahedron subdivided `subdivisions` times (20 * 4^subdivisions faces),
// vertices on the sphere of the given radius and centre, faces
// counter-clockwise seen from outside.
TriangleMesh icosphere(int subdivisions, float radius = 1.0f, const Eigen::Vector3f& centre = Eigen::Vector3f::Zero());

// The height field z = height(x, y) (0 without one) on an n x n grid of
// vertices `spacing` apart from the origin along +x and +y, two faces per
// square, counter-clockwise seen from +z.
TriangleMesh grid_mesh(int n, float spacing, const std::function<float(float, float)>& height = {});

// n points on the surfaces below, with Gaussian noise of standard deviation
// `noise` along the normal; exact outward normals.
PointCloud sample_sphere(int n, double radius, double noise, unsigned seed);
PointCloud sample_torus(int n, double major, double minor, double noise, unsigned seed);
// Box [-a, a]^3 with edges rounded by radius r (a > r).
PointCloud sample_rounded_box(int n, double a, double r, double noise, unsigned seed);
// Square patch [-s, s]^2 in the plane z = 0, normals +z.
PointCloud sample_plane_patch(int n, double s, double noise, unsigned seed);

// Replaces every normal by the closest of the 6 axis directions: a shape
// "scanned from 6 directions" with one orientation per scan.
void coarsen_to_axis_directions(PointCloud& points);

}  // namespace hos::synth
