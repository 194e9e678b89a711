#include "recon/domain.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace hos::recon {

int domain_levels(double longest_nodes) {
  int levels = 5;
  for (; longest_nodes > 600.0 && levels < 12; longest_nodes /= 2.0) ++levels;
  return levels;
}

GridGeometry make_domain(const BoundingBox& box, const ReconOptions& options, int levels) {
  const Eigen::Vector3d extent = box.extent().cast<double>();
  const double longest = extent.maxCoeff();
  const Eigen::Vector3d side = extent.array() + 2.0 * options.margin * longest;
  GridGeometry g;
  g.spacing = options.voxel_size > 0.0 ? options.voxel_size : side.maxCoeff() / options.resolution;
  if (levels <= 0) levels = domain_levels(side.maxCoeff() / g.spacing);
  for (int a = 0; a < 3; ++a) {
    // At least a few nodes across every axis, also for flat point sets; at
    // most kMaxDomainNodes, counted in double so that a tiny voxel size
    // cannot overflow (the memory check then refuses such a grid).
    const double wanted = std::ceil(side[a] / g.spacing) + 1.0;
    const int nodes = static_cast<int>(
        std::clamp(std::isfinite(wanted) ? wanted : kMaxDomainNodes, 8.0, static_cast<double>(kMaxDomainNodes)));
    g.dims[a] = admissible_dims(nodes, levels);
  }
  g.origin = box.center().cast<double>() - 0.5 * g.spacing * (g.dims.cast<double>().array() - 1.0).matrix();
  return g;
}

int band_only_start_level(const GridGeometry& grid) {
  constexpr std::int64_t kWholeGridNodes = std::int64_t{1} << 22;
  int level = 2;
  GridGeometry g = grid.coarsened().coarsened();
  while (g.num_nodes() > kWholeGridNodes && g.can_coarsen(3)) {
    g = g.coarsened();
    ++level;
  }
  return level;
}

bool keeps_only_band(const GridGeometry& grid, const ReconOptions& o) {
  const std::int64_t above = std::int64_t{o.solver.band_storage_above_mnodes} * 1000000;
  return o.energy != SmoothnessEnergy::kTotalVariation && o.solver.band_voxels > 0 && o.uniform_flux &&
         o.direction_filter_passes % 4 == 0 && grid.can_coarsen(3) && o.trim.enabled &&
         o.trim.distance_voxels + 2.0 <= o.solver.band_only_voxels && grid.num_nodes() > above;
}

}  // namespace hos::recon
