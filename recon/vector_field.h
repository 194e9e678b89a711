// The orientation field F of paper sec. 4.1: every sample's (coarse) normal is
// splatted trilinearly to its 8 grid nodes, smoothed by a box filter applied
// several times (a Gaussian approximation), and differentiated.
#pragma once

#include <array>
#include <vector>

#include "core/types.h"
#include "recon/active_nodes.h"
#include "recon/grid.h"

namespace hos::recon {

struct VectorGrid {
  GridGeometry geometry;
  std::array<std::vector<double>, 3> components;
};

// Splats normals (weighted by weights, if not empty) onto the grid.
VectorGrid splat_normals(const GridGeometry& geometry,
                         const std::vector<Eigen::Vector3f>& points,
                         const std::vector<Eigen::Vector3f>& normals,
                         const std::vector<float>& weights);

// Replaces the magnitude of the smoothed field by the smoothed sample density
// (density: the splat of the weights, filtered the same way). Coarse
// orientations (one per scan) then still carry a uniform flux across the
// surface: only their smoothed direction is used. Without it, the flux drops
// with the cosine of the orientation error and the isosurface moves within
// the transition band where orientations are poor.
void use_density_magnitude(VectorGrid& field, const std::vector<double>& density);

// The field of use_density_magnitude built in one go: the density splatted
// and filtered (density_passes) on the grid, the directions splatted and
// filtered on the grid coarsened once with direction_passes / 4 passes (each
// pass of the 3-tap box adds 2/3 of a squared spacing, so the smoothing has
// the same width at 1/32 of the work), then interpolated to the nodes where
// the density is not zero. Falls back to the fine grid when direction_passes
// is not a multiple of 4 or the grid cannot be coarsened.
VectorGrid density_scaled_field(const GridGeometry& geometry,
                                const std::vector<Eigen::Vector3f>& points,
                                const std::vector<Eigen::Vector3f>& normals,
                                const std::vector<float>& weights,
                                int density_passes,
                                int direction_passes);

// Splats the weights (1 per point if empty) as a scalar density.
std::vector<double> splat_density(const GridGeometry& geometry,
                                  const std::vector<Eigen::Vector3f>& points,
                                  const std::vector<float>& weights);

// Applies the 3-tap box filter [1 1 1]/3 along x, y and z, passes times.
void box_filter(VectorGrid& field, int passes);
template <typename T>  // float or double
void box_filter(const GridGeometry& geometry, std::vector<T>& values, int passes);

// Scales F so that integrating it across the surface gives a jump of about
// one in f: mean |F| at the samples times the filter's width becomes 1.
void normalize_field(VectorGrid& field, const std::vector<Eigen::Vector3f>& points, int filter_passes);

// Divergence by central differences (zero beyond the grid).
ScalarGrid divergence(const VectorGrid& field);

// Box-filter passes of the field of density_scaled_rhs: of the sample density
// and of the coarse directions (density_scaled_field), and the filter width
// normalize_field scales by.
struct FieldPasses {
  int density = 0;
  int direction = 0;
  int filter = 0;
};

// The right-hand side -div F of the energy (paper sec. 4.1) for the field of
// density_scaled_field scaled by normalize_field (passes.filter), the same
// values up to rounding. With coarse directions it evaluates F plane by plane
// from the fine density and the coarse directions, so the fine density and the
// result are its only grid-sized arrays (the materialised field is 3 more);
// otherwise it materialises F.
ScalarGrid density_scaled_rhs(const GridGeometry& geometry,
                              const std::vector<Eigen::Vector3f>& points,
                              const std::vector<Eigen::Vector3f>& normals,
                              const std::vector<float>& weights,
                              const FieldPasses& passes);

// density_scaled_rhs on the stored nodes of a band around the samples that
// holds every nonzero value (nodes within passes.density + 1 of a sample's
// cell), with the same values, and no grid-sized array: for grids too large
// for one. Needs passes.direction % 4 == 0 and a grid that coarsens.
StoredField density_scaled_rhs_near_samples(const GridGeometry& geometry,
                                            const std::vector<Eigen::Vector3f>& points,
                                            const std::vector<Eigen::Vector3f>& normals,
                                            const std::vector<float>& weights,
                                            const FieldPasses& passes);

}  // namespace hos::recon
