// The screening term of the energy operator (see ScreeningTerm): S^T S of the
// trilinear interpolation at the samples, stored per touched node.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
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
// sweep: a touched node's row reads x only within its 27 neighbours. Kept per
// cell, each cell's matrix times x is computed once per sweep, as the sweep
// reaches the cell's plane (CellProducts), and the nodes' rows sum those.
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
  // (i', j + dy, k + dz), or null for a row outside the grid. Kept per cell,
  // the term reads the cells' products with x instead (CellProducts).
  template <typename T>
  void add_row(std::int64_t row,
               int begin,
               int end,
               const std::array<const T*, 9>& x_rows,
               const double* cell_products,
               T* y_row) const;

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
    std::int32_t samples;   // in the cell; more than kMaxListedSamples: moments
    std::int64_t values;    // index of its first value in values_
    std::int64_t products;  // index of its first product (cell_products)
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
  // The same from the cell's products with x: a listed sample's weight at c
  // times f there, or the moments' row c.
  double cell_row_product(const Cell& cell, int c, const double* products) const;
  // The products of the cells of plane z (lower corners at z) with x, x in
  // the layout of nodes; cells with a corner it does not store are skipped
  // (no active node's row reads them).
  template <typename T>
  void compute_cell_products(int z, const ActiveNodes& nodes, const T* x, double* products) const;
  template <typename T>
  friend class CellProducts;

  GridGeometry geometry_;
  double weight_ = 0.0;
  std::vector<Run> runs_;
  std::vector<std::int64_t> row_begin_;  // per grid row (j, k): first run
  // Per touched node its 27 coefficients (x fastest), or empty: the cells.
  std::vector<float> coefficients_;
  std::vector<Cell> cells_;
  std::int64_t num_products_ = 0;  // per listed sample 1, per cell of moments 8
  // The cells of plane z (lower corner at z, clamped to [-2, dims.z]) are
  // cells_[plane_cells_[z + 2] .. plane_cells_[z + 3]).
  std::vector<std::int64_t> plane_cells_;
  std::vector<float> values_;
  std::vector<float> row_sums_;           // per touched node, without the weight
  std::vector<std::int32_t> first_cell_;  // per touched node, and one past the last
  std::vector<std::int32_t> cells_of_node_;
  mutable std::shared_ptr<const ScreeningTerm> coarser_;
};

// Kept per cell (ScreeningTerm::kept_per_cell), the products of the cells'
// matrices with x that the rows of a sweep sum: each computed once per cell
// rather than once per corner (8 times), plane by plane as one thread's sweep
// reaches it, while x is in cache. Each thread of a sweep has its own.
template <typename T>
class CellProducts {
 public:
  CellProducts(const ScreeningTerm& term, const ActiveNodes& nodes, const T* x)
      : term_(term), nodes_(nodes), x_(x), products_(new double[term.num_products_]) {}
  // Computes the products node plane k reads (cell planes k - 1 and k)
  // unless done; k never decreases.
  void reach_plane(int k) {
    for (int z = std::max(next_, k - 1); z <= k; ++z) term_.compute_cell_products(z, nodes_, x_, products_.get());
    next_ = std::max(next_, k + 1);
  }
  const double* data() const { return products_.get(); }

 private:
  const ScreeningTerm& term_;
  const ActiveNodes& nodes_;
  const T* x_;
  std::unique_ptr<double[]> products_;          // only the planes reached are written
  int next_ = std::numeric_limits<int>::min();  // the planes below are done
};

// Defined here so that the operator's row sweep inlines them.

// Index in Cell::moments of entry (a, b) of the symmetric 8x8 matrix.
constexpr int moment_index(int a, int b) {
  const int lo = a < b ? a : b, hi = a < b ? b : a;
  return lo * 8 - lo * (lo - 1) / 2 + (hi - lo);
}

// moment_index as a table, for the loops over a row of the matrix.
constexpr std::array<std::array<std::uint8_t, 8>, 8> moment_index_table() {
  std::array<std::array<std::uint8_t, 8>, 8> table{};
  for (int a = 0; a < 8; ++a) {
    for (int b = 0; b < 8; ++b) table[a][b] = static_cast<std::uint8_t>(moment_index(a, b));
  }
  return table;
}
inline constexpr std::array<std::array<std::uint8_t, 8>, 8> kMomentIndex = moment_index_table();

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
    for (int b = 0; b < 8; ++b) sum += v[kMomentIndex[c][b]] * xc[b];
    return sum;
  }
  for (int s = 0; s < cell.samples; ++s, v += 8) {
    double at_sample = 0.0;  // f at the sample
    for (int b = 0; b < 8; ++b) at_sample += v[b] * xc[b];
    sum += v[c] * at_sample;
  }
  return sum;
}

// The same sums as cell_row_times, in the same order, on products computed
// beforehand: the two give the same bits.
inline double ScreeningTerm::cell_row_product(const Cell& cell, int c, const double* products) const {
  const double* p = products + cell.products;
  if (cell.samples > kMaxListedSamples) return p[c];
  const float* v = values_.data() + cell.values;
  double sum = 0.0;
  for (int s = 0; s < cell.samples; ++s, v += 8) sum += v[c] * p[s];
  return sum;
}

template <typename T>
void ScreeningTerm::compute_cell_products(int z, const ActiveNodes& nodes, const T* x, double* products) const {
  const Eigen::Vector3i d = geometry_.dims;
  // The stored runs holding the cells' four corner rows (dy, dz), kept while
  // the next cells (sorted along rows) lie in them.
  std::array<ActiveNodes::StoredWindow, 4> windows;
  std::array<std::int64_t, 4> window_rows;
  window_rows.fill(-1);
  for (std::int64_t q = plane_cells_[z + 2]; q < plane_cells_[z + 3]; ++q) {
    const Cell& cell = cells_[q];
    // x at the cell's corners (bits x, y, z); zero outside the grid.
    std::array<double, 8> xc{};
    // Its corners inside the grid along x: i0 <= i <= i1, xc[2 r + i - corner].
    const int i0 = std::max(cell.corner.x(), 0), i1 = std::min(cell.corner.x() + 1, d.x() - 1);
    const int first = i0 - cell.corner.x();
    bool stored = true;
    for (int r = 0; r < 4 && stored; ++r) {
      const int j = cell.corner.y() + (r & 1), k = cell.corner.z() + (r >> 1);
      if (j < 0 || k < 0 || j >= d.y() || k >= d.z() || i0 > i1) continue;
      const std::int64_t row = std::int64_t{k} * d.y() + j;
      ActiveNodes::StoredWindow& w = windows[r];
      if (window_rows[r] != row || i0 < w.lo || i0 >= w.hi) {
        w = nodes.stored_window(j, k, i0);
        window_rows[r] = row;
      }
      // A corner the layout does not store: no active node's row reads the cell.
      stored = i0 >= w.lo && i1 < w.hi;
      if (!stored) break;
      xc[2 * r + first] = static_cast<double>(x[w.base + i0]);
      if (i1 > i0) xc[2 * r + 1] = static_cast<double>(x[w.base + i1]);
    }
    if (!stored) continue;
    const float* v = values_.data() + cell.values;
    double* p = products + cell.products;
    if (cell.samples > kMaxListedSamples) {
      // Row c of the moments times x (cell_row_times).
      for (int c = 0; c < 8; ++c) {
        double sum = 0.0;
        for (int b = 0; b < 8; ++b) sum += v[kMomentIndex[c][b]] * xc[b];
        p[c] = sum;
      }
      continue;
    }
    for (int s = 0; s < cell.samples; ++s, v += 8) {
      double at_sample = 0.0;  // f at the sample
      for (int b = 0; b < 8; ++b) at_sample += v[b] * xc[b];
      p[s] = at_sample;
    }
  }
}

template <typename T>
void ScreeningTerm::add_row(std::int64_t row,
                            int begin,
                            int end,
                            const std::array<const T*, 9>& x_rows,
                            const double* cell_products,
                            T* y_row) const {
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
      double sum = 0.0;
      for_each_cell_of(run, i, [&](const Cell& cell, int c) { sum += cell_row_product(cell, c, cell_products); });
      y_row[i] += static_cast<T>(weight_ * sum);
    }
  }
}

}  // namespace hos::recon
