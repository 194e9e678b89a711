// Sets of grid nodes as runs along x, row after row: the shape of a band or a
// support around the samples, built and dilated without a grid-sized mask
// (at grid 1024 a byte per node is 0.8 GB, the runs of a band a few MB).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "recon/grid.h"

namespace hos::recon {

struct NodeRun {
  int begin = 0, end = 0;  // nodes begin <= i < end of one row
};

struct RowRuns {
  Eigen::Vector3i dims = Eigen::Vector3i::Zero();
  // Runs of row j + ny k are runs[row_begin[row]] .. runs[row_begin[row + 1]],
  // ascending and separated by at least one node.
  std::vector<std::int64_t> row_begin;
  std::vector<NodeRun> runs;

  std::int64_t rows() const { return std::int64_t{dims.y()} * dims.z(); }
  std::int64_t count() const;
  bool contains(int i, int j, int k) const;
};

// The corners of the cells holding the samples (the nodes their trilinear
// weights touch), inside the grid.
RowRuns sample_cell_corners(const GridGeometry& g, const std::vector<Eigen::Vector3f>& points);

// Every node within `radius` nodes of a node of the set along each axis (a box
// dilation), inside the grid.
RowRuns dilated(const RowRuns& set, int radius);

// The nodes all of whose in-grid neighbours within one node along each axis
// (the 3x3x3 box) are in the set: nodes outside the grid count as members.
RowRuns eroded_once(const RowRuns& set);

// Coarse node I sits on fine node 2I + 1: the coarse nodes whose fine node is
// in the set.
RowRuns coarse_nodes_on(const RowRuns& fine_set, const Eigen::Vector3i& coarse_dims);

}  // namespace hos::recon
