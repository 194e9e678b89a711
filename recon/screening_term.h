// The screening term of the energy operator (see ScreeningTerm): S^T S of the
// trilinear interpolation at the samples, stored per touched node.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "recon/active_nodes.h"
#include "recon/grid.h"

namespace hos::recon {

struct CellSamples;  // the samples sorted by the cell holding them (screening_term.cpp)

// Optional screening term weight * sum_i (f(p_i) - target)^2 over the samples
// (f(p_i) trilinear): it pins the level set to the samples where orientations
// are too coarse to place it (one orientation per scan). Every multigrid level
// rediscretises it from the sample positions at its own spacing, with the
// weight divided by 8 per level (the Galerkin scaling of R S^T S P with the
// restriction R = P^T / 8). S^T S is stored in one of two forms per level:
// per touched node its 27 coefficients (offsets (-1..1)^3), fastest to
// apply; or, where that takes more than twice the memory (samples sparse
// for the level's cells: the fine levels of large grids), per cell that
// holds samples: a cell of one sample keeps its trilinear weights w_s at its
// 8 corners, one of more the 36 distinct entries of sum_s w_s w_s^T. For the
// bunny's 362 k samples at grid 1024 the finest level's cells take 41 MB
// where its coefficients would take 238 MB. Either way the operator stays a row-local
// sweep: a touched node's row reads x only within its 27 neighbours.
class ScreeningTerm {
 public:
  ScreeningTerm() = default;
  ScreeningTerm(const GridGeometry& geometry, const std::vector<Eigen::Vector3f>& points, double weight);
  bool empty() const { return runs_.empty(); }
  // Is the term kept per cell (else per touched node)?
  bool kept_per_cell() const { return coefficients_.empty() && !runs_.empty(); }
  double weight() const { return weight_; }
  // Adds weight * target * S^T 1 (the target's share of the right-hand side)
  // to rhs, in the layout of nodes (which must store every touched node).
  void add_target(double target, const ActiveNodes& nodes, double* rhs) const;
  // Multiplies the weight by factor.
  void scale(double factor);
  // The term rediscretised on the coarsened grid from the same samples, with
  // the weight divided by 8; built once and shared by every operator that
  // holds this term (the band's hierarchy and the full grid's).
  std::shared_ptr<const ScreeningTerm> coarsened(const std::vector<Eigen::Vector3f>& points) const;
  // Mean l1 row sum over the touched nodes (weight * mean splatted density).
  double mean_row_sum() const;
  // Adds scale times its row sums (weight * splatted density; every
  // coefficient is >= 0, so also its l1 row sums) to y_row[i] for the touched
  // nodes i of grid row `row` (j + ny k) with begin <= i < end.
  template <typename T>
  void add_row_sums(std::int64_t row, int begin, int end, double scale, T* y_row) const;
  // y_row[i] += (S^T S x)[node i of the row] for the touched nodes with
  // begin <= i < end; x_rows[(dy + 1) + 3 (dz + 1)][i'] is x at node
  // (i', j + dy, k + dz), or null for a row outside the grid.
  template <typename T>
  void add_row(std::int64_t row, int begin, int end, const std::array<const T*, 9>& x_rows, T* y_row) const;

 private:
  // A cell that holds samples (corners as bits x, y, z). A cell of one
  // sample keeps its weights at the 8 corners in values_ from `values`; a
  // fuller one the upper triangle of sum_s w_s w_s^T there (36 values, see
  // moment_index), whose row takes 8 products where listing its n samples
  // would take 16 n.
  static constexpr int kMaxListedSamples = 1;
  // x = 1 at every corner: cell_row_times gives the row's sum.
  static constexpr std::array<double, 8> kAllOnes = {1, 1, 1, 1, 1, 1, 1, 1};
  struct Cell {
    Eigen::Vector3i corner;
    std::int32_t samples;  // in the cell; more than kMaxListedSamples: moments
    std::int64_t values;   // index of its first value in values_
  };
  // The touched nodes as runs of consecutive nodes along x (the rows a span
  // meets are found without a search); node e of the runs (in run order) is
  // corner c of cell q for every 8 q + c in
  // cells_of_node_[first_cell_[e] .. first_cell_[e + 1]).
  struct Run {
    int j, k, begin, end;  // grid row and nodes begin <= i < end
    std::int64_t first;    // index of the run's first node among the touched nodes
  };
  // The construction's steps: the cells' values (cells_, values_); per
  // touched node the cells it is a corner of (corners: per cell the touched
  // node of each corner, -1 outside the grid); the runs of touched nodes
  // (ascending), indexed per row; the row sums; and, where they are kept,
  // the cells' matrices as 27 coefficients per touched node.
  void store_cells(const CellSamples& cells);
  void index_cells_of_nodes(const std::vector<std::array<std::int64_t, 8>>& corners, std::size_t num_nodes);
  void index_runs(const std::vector<std::int64_t>& nodes);
  void compute_row_sums();
  void accumulate_coefficients(const std::vector<std::array<std::int64_t, 8>>& corners);
  // Calls fn(cell, c) for the cells node i of run e is corner c of.
  template <typename Fn>
  void for_each_cell_of(const Run& run, int i, Fn&& fn) const;
  // Row c of the cell's matrix sum_s w_s w_s^T times xc (its corners' values).
  double cell_row_times(const Cell& cell, int c, const std::array<double, 8>& xc) const;

  GridGeometry geometry_;
  double weight_ = 0.0;
  std::vector<Run> runs_;
  std::vector<std::int64_t> row_begin_;  // per grid row (j, k): first run
  // Per touched node its 27 coefficients (x fastest), or empty: the cells.
  std::vector<float> coefficients_;
  std::vector<Cell> cells_;
  std::vector<float> values_;
  std::vector<float> row_sums_;           // per touched node, without the weight
  std::vector<std::int32_t> first_cell_;  // per touched node, and one past the last
  std::vector<std::int32_t> cells_of_node_;
  mutable std::shared_ptr<const ScreeningTerm> coarser_;
};

// Defined here so that the operator's row sweep inlines them.

// Index in Cell::moments of entry (a, b) of the symmetric 8x8 matrix.
constexpr int moment_index(int a, int b) {
  const int lo = a < b ? a : b, hi = a < b ? b : a;
  return lo * 8 - lo * (lo - 1) / 2 + (hi - lo);
}

// For a node that is corner c of a cell, where its corner b lies: the row
// (dy + 1) + 3 (dz + 1) of the 9 rows around the node, the offset along x,
// and the entry (c, b) in Cell::moments.
struct CellCornerTap {
  int row, dx, moment;
};
constexpr std::array<std::array<CellCornerTap, 8>, 8> cell_corner_taps() {
  std::array<std::array<CellCornerTap, 8>, 8> taps{};
  for (int c = 0; c < 8; ++c) {
    for (int b = 0; b < 8; ++b) {
      const int dx = (b & 1) - (c & 1), dy = ((b >> 1) & 1) - ((c >> 1) & 1), dz = (b >> 2) - (c >> 2);
      taps[c][b] = {(dy + 1) + 3 * (dz + 1), dx, moment_index(c, b)};
    }
  }
  return taps;
}
inline constexpr std::array<std::array<CellCornerTap, 8>, 8> kCellCornerTaps = cell_corner_taps();

template <typename Fn>
void ScreeningTerm::for_each_cell_of(const Run& run, int i, Fn&& fn) const {
  const std::int64_t node = run.first + (i - run.begin);
  for (std::int32_t t = first_cell_[node]; t < first_cell_[node + 1]; ++t) {
    fn(cells_[cells_of_node_[t] >> 3], cells_of_node_[t] & 7);
  }
}

template <typename T>
void ScreeningTerm::add_row_sums(std::int64_t row, int begin, int end, double scale, T* y_row) const {
  if (runs_.empty()) return;
  for (std::int64_t e = row_begin_[row]; e < row_begin_[row + 1]; ++e) {
    const Run& run = runs_[e];
    for (int i = std::max(run.begin, begin); i < std::min(run.end, end); ++i) {
      y_row[i] += static_cast<T>(scale * weight_ * row_sums_[run.first + (i - run.begin)]);
    }
  }
}

inline double ScreeningTerm::cell_row_times(const Cell& cell, int c, const std::array<double, 8>& xc) const {
  const float* v = values_.data() + cell.values;
  double sum = 0.0;
  if (cell.samples > kMaxListedSamples) {
    for (int b = 0; b < 8; ++b) sum += v[moment_index(c, b)] * xc[b];
    return sum;
  }
  for (int s = 0; s < cell.samples; ++s, v += 8) {
    double at_sample = 0.0;  // f at the sample
    for (int b = 0; b < 8; ++b) at_sample += v[b] * xc[b];
    sum += v[c] * at_sample;
  }
  return sum;
}

template <typename T>
void ScreeningTerm::add_row(
    std::int64_t row, int begin, int end, const std::array<const T*, 9>& x_rows, T* y_row) const {
  const Eigen::Vector3i d = geometry_.dims;
  for (std::int64_t e = row_begin_[row]; e < row_begin_[row + 1]; ++e) {
    const Run& run = runs_[e];
    // Every neighbour of the run's nodes inside the grid: no checks.
    const bool interior = run.j > 0 && run.j < d.y() - 1 && run.k > 0 && run.k < d.z() - 1;
    if (!coefficients_.empty()) {
      for (int i = std::max(run.begin, begin); i < std::min(run.end, end); ++i) {
        const float* c = coefficients_.data() + 27 * (run.first + (i - run.begin));
        T sum = 0;
        if (interior && i > 0 && i < d.x() - 1) {
          // A fixed 27-term sum, three neighbours along x from each of the 9 rows.
          for (int q = 0; q < 9; ++q) {
            const T* p = x_rows[q] + (i - 1);
            sum += static_cast<T>(c[3 * q]) * p[0] + static_cast<T>(c[3 * q + 1]) * p[1] +
                   static_cast<T>(c[3 * q + 2]) * p[2];
          }
        } else {
          for (int q = 0; q < 27; ++q) {
            const int ii = i + q % 3 - 1;
            // Neighbours outside the grid have zero coefficients: skip them.
            if (x_rows[q / 3] && ii >= 0 && ii < d.x()) sum += static_cast<T>(c[q]) * x_rows[q / 3][ii];
          }
        }
        y_row[i] += static_cast<T>(weight_) * sum;
      }
      continue;
    }
    for (int i = std::max(run.begin, begin); i < std::min(run.end, end); ++i) {
      const bool inside = interior && i > 0 && i < d.x() - 1;
      double sum = 0.0;
      for_each_cell_of(run, i, [&](const Cell& cell, int c) {
        // x at the cell's corners; corners outside the grid are zero ghosts.
        std::array<double, 8> xc;
        for (int b = 0; b < 8; ++b) {
          const CellCornerTap& tap = kCellCornerTaps[c][b];
          const T* x = x_rows[tap.row];
          const int ii = i + tap.dx;
          xc[b] = inside || (x && ii >= 0 && ii < d.x()) ? static_cast<double>(x[ii]) : 0.0;
        }
        sum += cell_row_times(cell, c, xc);
      });
      y_row[i] += static_cast<T>(weight_ * sum);
    }
  }
}

}  // namespace hos::recon
