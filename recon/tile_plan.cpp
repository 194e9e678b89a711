#include "recon/tile_plan.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/reporter.h"
#include "core/statistics.h"
#include "recon/domain.h"
#include "recon/memory_budget.h"

namespace hos::recon {
namespace {

// A cut leaves at least this many nodes on either side of it, so every core
// holds cells to mesh and a median to cut at.
constexpr int kMinCoreNodes = 4;
constexpr int kMaxTiles = 4096;
// Fitted like memory_budget.cpp's constants: a join's fixed part, and per
// node of the grown core the blended value, the two sums and a tile's piece
// (8 + 8 + 8 + 4) plus the extraction's layout.
constexpr double kJoinFixedBytes = 16.0 * 1024 * 1024;
constexpr double kJoinBytesPerNode = 40.0;

double smoothstep(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// Continuous lattice coordinates of a sample.
Eigen::Vector3d lattice_coordinates(const GridGeometry& lattice, const Eigen::Vector3f& p) {
  return lattice.to_grid(p.cast<double>());
}

bool inside(const NodeBox& box, const Eigen::Vector3d& u) {
  return (u.array() >= box.lo.cast<double>().array()).all() && (u.array() <= box.hi.cast<double>().array()).all();
}

std::vector<Eigen::Vector3f> points_in(const std::vector<Eigen::Vector3f>& points,
                                       const GridGeometry& lattice,
                                       const NodeBox& box) {
  std::vector<Eigen::Vector3f> in;
  for (const auto& p : points) {
    if (inside(box, lattice_coordinates(lattice, p))) in.push_back(p);
  }
  return in;
}

// recon.lambda for a grid whose longest side differs from the lattice's: the
// smoothness weight is lambda * (D / 50)^2 for the Hessian energies, lambda *
// D / 50 for TV and lambda for the membrane (D the grid's longest side,
// recon_options.h), so lambda is scaled by the ratio of the sides to that power.
double scaled_lambda(const ReconOptions& options, const GridGeometry& lattice, const GridGeometry& grid) {
  const double ratio = static_cast<double>(lattice.dims.maxCoeff() + 1) / static_cast<double>(grid.dims.maxCoeff() + 1);
  switch (options.energy) {
    case SmoothnessEnergy::kMembrane:
      return options.lambda;
    case SmoothnessEnergy::kTotalVariation:
      return options.lambda * ratio;
    case SmoothnessEnergy::kPureSecond:
    case SmoothnessEnergy::kFullHessian:
      break;
  }
  return options.lambda * ratio * ratio;
}

// The extended box, solve grid, samples and estimate of a tile whose core
// and neighbours are set.
void complete_tile(Tile& tile,
                   const std::vector<Eigen::Vector3f>& points,
                   const GridGeometry& lattice,
                   const ReconOptions& options) {
  const int overlap = options.tile_overlap_voxels;
  for (int a = 0; a < 3; ++a) {
    tile.extended.lo[a] = std::max(0, tile.core.lo[a] - (tile.neighbour_below[a] ? overlap : 0));
    tile.extended.hi[a] = std::min(lattice.dims[a] - 1, tile.core.hi[a] + (tile.neighbour_above[a] ? overlap : 0));
  }
  // A margin beyond the faces with a neighbour, as make_domain leaves around
  // the points (the lattice's own faces have the whole run's margin), and
  // dims that coarsen like the whole run's.
  const Eigen::Vector3i span = tile.extended.hi - tile.extended.lo;
  const int margin = static_cast<int>(std::ceil(options.margin * span.maxCoeff()));
  Eigen::Vector3i lo = tile.extended.lo, hi = tile.extended.hi;
  for (int a = 0; a < 3; ++a) {
    if (tile.neighbour_below[a]) lo[a] -= margin;
    if (tile.neighbour_above[a]) hi[a] += margin;
  }
  const Eigen::Vector3i wanted = hi - lo + Eigen::Vector3i::Ones();
  const int levels = domain_levels(wanted.maxCoeff());
  for (int a = 0; a < 3; ++a) {
    tile.grid.dims[a] = admissible_dims(wanted[a], levels);
    lo[a] -= (tile.grid.dims[a] - wanted[a]) / 2;
  }
  tile.grid.spacing = lattice.spacing;
  tile.grid.origin = lattice.position(lo.x(), lo.y(), lo.z());
  tile.grid_offset = lo;
  const std::vector<Eigen::Vector3f> in = points_in(points, lattice, tile.extended);
  tile.num_samples = in.size();
  ReconOptions tile_opts = options;
  tile_opts.lambda = scaled_lambda(options, lattice, tile.grid);
  tile.estimated_peak_bytes = std::max(estimate_peak_bytes(tile.grid, in, tile_opts), estimate_join_bytes(tile.core));
}

// Splits tile at the median of its core's samples along its longest axis
// (the next longest when a cut there would leave a side too thin); false
// when no axis can be cut.
bool split(std::vector<Tile>& tiles,
           std::size_t index,
           const std::vector<Eigen::Vector3f>& points,
           const GridGeometry& lattice,
           const ReconOptions& options) {
  const Tile tile = tiles[index];
  std::array<int, 3> axes = {0, 1, 2};
  const Eigen::Vector3i span = tile.core.hi - tile.core.lo;
  std::stable_sort(axes.begin(), axes.end(), [&](int a, int b) { return span[a] > span[b]; });
  for (int axis : axes) {
    if (span[axis] < 2 * kMinCoreNodes) continue;
    std::vector<double> along;
    for (const auto& p : points) {
      const Eigen::Vector3d u = lattice_coordinates(lattice, p);
      if (inside(tile.core, u)) along.push_back(u[axis]);
    }
    const double median =
        along.empty() ? 0.5 * (tile.core.lo[axis] + tile.core.hi[axis]) : upper_median(std::move(along));
    const int cut = std::clamp(static_cast<int>(std::lround(median)), tile.core.lo[axis] + kMinCoreNodes,
                               tile.core.hi[axis] - kMinCoreNodes);
    Tile below = tile, above = tile;
    below.core.hi[axis] = cut;
    below.neighbour_above[axis] = true;
    above.core.lo[axis] = cut;
    above.neighbour_below[axis] = true;
    complete_tile(below, points, lattice, options);
    complete_tile(above, points, lattice, options);
    tiles[index] = below;
    tiles.push_back(above);
    return true;
  }
  return false;
}

std::size_t largest(const std::vector<Tile>& tiles) {
  std::size_t at = 0;
  for (std::size_t t = 1; t < tiles.size(); ++t) {
    if (tiles[t].estimated_peak_bytes > tiles[at].estimated_peak_bytes) at = t;
  }
  return at;
}

}  // namespace

TilePlan plan_tiles(const std::vector<Eigen::Vector3f>& points,
                    const GridGeometry& lattice,
                    const ReconOptions& unit_options,
                    int tiles,
                    std::size_t budget_bytes) {
  TilePlan plan;
  plan.lattice = lattice;
  plan.options = unit_options;
  plan.whole_estimated_peak_bytes = estimate_peak_bytes(lattice, points, unit_options);
  Tile whole;
  whole.core = NodeBox{Eigen::Vector3i::Zero(), lattice.dims - Eigen::Vector3i::Ones()};
  whole.extended = whole.core;
  whole.grid = lattice;
  whole.num_samples = points.size();
  whole.estimated_peak_bytes = plan.whole_estimated_peak_bytes;
  plan.tiles.push_back(whole);
  const auto done = [&] {
    if (tiles > 0) return static_cast<int>(plan.tiles.size()) >= tiles;
    return plan.tiles[largest(plan.tiles)].estimated_peak_bytes <= budget_bytes;
  };
  const auto refuse = [&](std::size_t at) {
    return ConfigError(
        "recon.tiles",
        format_message("the ", lattice.dims.x(), "x", lattice.dims.y(), "x", lattice.dims.z(),
                       " grid cannot be cut into ",
                       tiles > 0 ? format_message(tiles, " tiles") : std::string("tiles that fit the budget"),
                       ": tile ", at, " (", plan.tiles[at].core.hi.x() - plan.tiles[at].core.lo.x() + 1, "x",
                       plan.tiles[at].core.hi.y() - plan.tiles[at].core.lo.y() + 1, "x",
                       plan.tiles[at].core.hi.z() - plan.tiles[at].core.lo.z() + 1, " nodes, about ",
                       megabytes(plan.tiles[at].estimated_peak_bytes),
                       ") is as small as tiles get; give a "
                       "coarser grid (recon.resolution, recon.voxel_size) or a larger recon.max_memory_mb"));
  };
  // A grid that even kMaxTiles tiles of the budget at one byte a node cannot
  // hold is refused before any estimate (whose byte counts would overflow).
  const double nodes = double(lattice.dims.x()) * lattice.dims.y() * lattice.dims.z();
  if (nodes > double(kMaxTiles) * double(budget_bytes)) throw refuse(0);
  while (!done()) {
    const std::size_t at = largest(plan.tiles);
    if (static_cast<int>(plan.tiles.size()) >= kMaxTiles || !split(plan.tiles, at, points, lattice, unit_options)) {
      throw refuse(at);
    }
  }
  // The tiles asked for must fit as well: a tile's solve or its core's join
  // over the budget would be refused, or killed, only after the other tiles ran.
  const std::size_t at = largest(plan.tiles);
  if (plan.tiles[at].estimated_peak_bytes > budget_bytes) {
    throw ConfigError("recon.tiles",
                      format_message("tile ", at, " of ", plan.tiles.size(), " needs about ",
                                     megabytes(plan.tiles[at].estimated_peak_bytes),
                                     " to solve or to join, more than the budget of ", megabytes(budget_bytes),
                                     " (recon.max_memory_mb); give more tiles, or 0 to let the budget choose"));
  }
  return plan;
}

OrientedSamples tile_samples(const OrientedSamples& samples, const TilePlan& plan, const Tile& tile) {
  OrientedSamples out;
  out.frame = samples.frame;
  for (std::size_t i = 0; i < samples.points.size(); ++i) {
    if (!inside(tile.extended, lattice_coordinates(plan.lattice, samples.points[i]))) continue;
    out.points.push_back(samples.points[i]);
    out.normals.push_back(samples.normals[i]);
    if (!samples.weights.empty()) out.weights.push_back(samples.weights[i]);
  }
  return out;
}

ReconOptions tile_options(const TilePlan& plan, const Tile& tile) {
  ReconOptions o = plan.options;
  o.lambda = scaled_lambda(plan.options, plan.lattice, tile.grid);
  return o;
}

double blend_weight(const Tile& tile, const Eigen::Vector3i& node, TileBlend blend) {
  if (!tile.extended.contains(node)) return 0.0;
  if (blend == TileBlend::kSwitch) return tile.core.contains(node) ? 1.0 : 0.0;
  double w = 1.0;
  for (int a = 0; a < 3; ++a) {
    if (tile.neighbour_below[a] && node[a] < tile.core.lo[a]) {
      w *= smoothstep(double(node[a] - tile.extended.lo[a]) / double(tile.core.lo[a] - tile.extended.lo[a]));
    }
    if (tile.neighbour_above[a] && node[a] > tile.core.hi[a]) {
      w *= smoothstep(double(tile.extended.hi[a] - node[a]) / double(tile.extended.hi[a] - tile.core.hi[a]));
    }
  }
  return w;
}

std::size_t estimate_join_bytes(const NodeBox& core) {
  return static_cast<std::size_t>(kJoinFixedBytes + kJoinBytesPerNode * static_cast<double>(core.grown(1).num_nodes()));
}

}  // namespace hos::recon
