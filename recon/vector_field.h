// The orientation field F of paper sec. 4.1: every sample's (coarse) normal is
// splatted trilinearly to its 8 grid nodes, smoothed by a box filter applied
// several times (a Gaussian approximation), and differentiated.
#pragma once

#include <array>
#include <vector>

#include "core/types.h"
#include "recon/grid.h"

namespace hos::recon {

struct VectorGrid {
  GridGeometry geometry;
  std::array<std::vector<double>, 3> components;
};

// Splats normals (weighted by weights, if not empty) onto the grid.
VectorGrid splat_normals(const GridGeometry& geometry, const std::vector<Eigen::Vector3f>& points,
                         const std::vector<Eigen::Vector3f>& normals,
                         const std::vector<float>& weights);

// Applies the 3-tap box filter [1 1 1]/3 along x, y and z, passes times.
void box_filter(VectorGrid& field, int passes);

// Scales F so that integrating it across the surface gives a jump of about
// one in f: mean |F| at the samples times the filter's width becomes 1.
void normalize_field(VectorGrid& field, const std::vector<Eigen::Vector3f>& points,
                     int filter_passes);

// Divergence by central differences (zero beyond the grid).
ScalarGrid divergence(const VectorGrid& field);

}  // namespace hos::recon
