// The grid resolution the samples support (recon.resolution 0). A grid much
// finer than the samples' spacing leaves cells without a sample all over the
// surface: trimming then opens holes and the noise of single points becomes
// bumps; a much coarser one throws away detail the points carry (on the
// Strecha sets, dense points from 640 px matching, grid 512 instead of 256
// raised the held-out PSNR by about 1 dB). The density rule finds the
// finest grid at which the cells that hold samples hold, on average, a given
// number of them: the surface is then covered without gaps at any scale of
// scene, photo size or point count.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/types.h"
#include "recon/recon_options.h"

namespace hos::recon {

// The resolutions the density rule chooses among: coarser grids lose the
// shape; the finest is recon.resolution's, the memory budget tiles or caps
// the grid (points from photos matched at 2048 px support about 2000 cells
// across a facade: a cap at 1024 cost fountain-P11's held-out photo 1.8 dB).
constexpr int kMinDensityResolution = 64;
constexpr int kMaxDensityResolution = kMaxResolution;

// Samples per cell that holds any, on the grid of `resolution` cells along
// the longest side of the domain of `box` (make_domain with options' margin).
double mean_samples_per_occupied_cell(const BoundingBox& box,
                                      const std::vector<Eigen::Vector3f>& points,
                                      const ReconOptions& options,
                                      int resolution);

// The largest resolution in [kMinDensityResolution, kMaxDensityResolution]
// whose occupied cells hold at least options.samples_per_cell samples on
// average (kMinDensityResolution when none does).
int resolution_from_density(const BoundingBox& box,
                            const std::vector<Eigen::Vector3f>& points,
                            const ReconOptions& options);

}  // namespace hos::recon
