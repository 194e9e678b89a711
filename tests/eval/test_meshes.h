// Analytic meshes for the eval tests (spheres: synth/shapes.h).
#pragma once

#include <Eigen/Core>

#include "core/types.h"

namespace hos::eval::testing {

// Axis-aligned cube [offset, offset + size]^3, each side split into n x n
// squares of two triangles, outward counter-clockwise faces, shared vertices.
TriangleMesh cube(float size, const Eigen::Vector3f& offset, int n = 1);

}  // namespace hos::eval::testing
