// The tiles of a tiled reconstruction (docs/scale.md, "Design: tiled
// reconstruction"): the whole run's grid (the lattice) is cut at the median
// of the samples along a tile's longest axis until there are as many tiles as
// asked or every tile's estimated peak fits the memory budget. Each tile's
// core is a box of lattice nodes (neighbouring cores share their boundary
// nodes); it is extended by the overlap on every side with a neighbour, and
// solved alone, from the samples in its extended box, on a grid of the same
// lattice. Every process of a split run computes the same plan from the same
// samples and options.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "recon/grid.h"
#include "recon/recon_options.h"
#include "recon/sample_frame.h"

namespace hos::recon {

// The lattice nodes lo <= n <= hi (per axis).
struct NodeBox {
  Eigen::Vector3i lo = Eigen::Vector3i::Zero();
  Eigen::Vector3i hi = Eigen::Vector3i::Constant(-1);

  bool empty() const { return (hi.array() < lo.array()).any(); }
  std::int64_t num_nodes() const {
    return empty() ? 0 : std::int64_t{hi.x() - lo.x() + 1} * (hi.y() - lo.y() + 1) * (hi.z() - lo.z() + 1);
  }
  bool contains(const Eigen::Vector3i& n) const {
    return (n.array() >= lo.array()).all() && (n.array() <= hi.array()).all();
  }
  NodeBox intersected(const NodeBox& o) const { return {lo.cwiseMax(o.lo), hi.cwiseMin(o.hi)}; }
  // Grown by r nodes on every side.
  NodeBox grown(int r) const { return {lo.array() - r, hi.array() + r}; }
};

struct Tile {
  NodeBox core;                                              // the nodes whose cells this tile meshes
  NodeBox extended;                                          // core + the overlap on every side with a neighbour
  std::array<bool, 3> neighbour_below{}, neighbour_above{};  // per axis
  GridGeometry grid;                                         // the tile's solve grid, on the lattice
  Eigen::Vector3i grid_offset = Eigen::Vector3i::Zero();     // lattice node of grid node (0, 0, 0)
  std::size_t num_samples = 0;                               // in the extended box
  std::size_t estimated_peak_bytes = 0;                      // of its solve or its core's join, the larger
};

struct TilePlan {
  GridGeometry lattice;  // the whole run's grid, in the samples' unit frame
  ReconOptions options;  // the whole run's, in the unit frame (choose_run_grid)
  std::vector<Tile> tiles;
  std::size_t whole_estimated_peak_bytes = 0;  // of the whole grid solved at once
};

// The plan for samples (unit frame) on the whole run's grid with its options
// (choose_run_grid): `tiles` tiles (>= 1), or with tiles 0 as few as keep
// every tile's estimate within `budget_bytes` (one when the whole grid
// fits). Throws ConfigError(recon.tiles) when the cores cannot be cut that
// small (a few nodes wide).
TilePlan plan_tiles(const std::vector<Eigen::Vector3f>& points,
                    const GridGeometry& lattice,
                    const ReconOptions& unit_options,
                    int tiles,
                    std::size_t budget_bytes);

// The samples inside the tile's extended box (the same frame).
OrientedSamples tile_samples(const OrientedSamples& samples, const TilePlan& plan, const Tile& tile);

// The options a tile is solved with: the whole run's, with recon.lambda scaled
// so that the smoothness weight, lambda times a power of the grid's longest
// side (recon_options.h), is the whole run's: the same smoothing length in
// scene units on a smaller grid.
ReconOptions tile_options(const TilePlan& plan, const Tile& tile);

// The tile's weight at a lattice node: with kSmooth 1 in the core, falling to
// 0 at the extended box's face on every side with a neighbour as a
// smoothstep (C1) of the distance, so a tile's distorted rim never counts;
// with kSwitch 1 in the core, else 0. Zero outside the extended box.
double blend_weight(const Tile& tile, const Eigen::Vector3i& node, TileBlend blend);

// Peak bytes of joining one core (blend_and_extract_core): per node of the
// core grown by one, the blended value, the weights' sums and a tile's piece.
std::size_t estimate_join_bytes(const NodeBox& core);

}  // namespace hos::recon
