// Analytic meshes for the eval tests.
#pragma once

#include <Eigen/Core>

#include "core/types.h"

namespace hos::testing {

// Icosahedron subdivided `levels` times, vertices projected onto the sphere of
// the given radius and centre; faces counter-clockwise seen from outside.
TriangleMesh icosphere(int levels, double radius, const Eigen::Vector3f& centre = Eigen::Vector3f::Zero());

// Axis-aligned cube [offset, offset + size]^3, each side split into n x n
// squares of two triangles, outward counter-clockwise faces, shared vertices.
TriangleMesh cube(float size, const Eigen::Vector3f& offset, int n = 1);

}  // namespace hos::testing
