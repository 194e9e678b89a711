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

// Optional screening term weight * sum_i (f(p_i) - target)^2 over the samples
// (f(p_i) trilinear): it pins the level set to the samples where orientations
// are too coarse to place it (one orientation per scan). Every multigrid level
// rediscretises it from the sample positions at its own spacing, with the
// weight divided by 8 per level (the Galerkin scaling of R S^T S P with the
// restriction R = P^T / 8), and stores S^T S as a 27-point stencil on the
// nodes it touches, so the operator stays a row-local sweep.
class ScreeningTerm {
 public:
  ScreeningTerm() = default;
  ScreeningTerm(const GridGeometry& geometry, const std::vector<Eigen::Vector3f>& points, double weight);
  bool empty() const { return runs_.empty(); }
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
  GridGeometry geometry_;
  double weight_ = 0.0;
  // The touched nodes as runs of consecutive nodes along x (the rows a span
  // meets are found without a search), each node's 27 coefficients (offsets
  // (-1..1)^3, x fastest) contiguous.
  struct Run {
    int j, k, begin, end;       // grid row and nodes begin <= i < end
    std::int64_t coefficients;  // index of the run's first coefficient
    bool interior;              // all 27 neighbours of every node inside the grid
  };
  // Splits the touched nodes (ascending) into runs_ and indexes them per row.
  void index_runs(const std::vector<std::int64_t>& nodes);

  std::vector<Run> runs_;
  std::vector<std::int64_t> row_begin_;  // per grid row (j, k): first run
  std::vector<float> coefficients_;
  std::int64_t num_nodes_ = 0;
  mutable std::shared_ptr<const ScreeningTerm> coarser_;
};

// Defined here so that the operator's row sweep inlines them.
template <typename T>
void ScreeningTerm::add_row_sums(std::int64_t row, int begin, int end, double scale, T* y_row) const {
  if (runs_.empty()) return;
  for (std::int64_t e = row_begin_[row]; e < row_begin_[row + 1]; ++e) {
    const Run& run = runs_[e];
    const int i0 = std::max(run.begin, begin), i1 = std::min(run.end, end);
    const float* c = coefficients_.data() + run.coefficients + 27 * (i0 - run.begin);
    for (int i = i0; i < i1; ++i, c += 27) {
      double sum = 0.0;
      for (int q = 0; q < 27; ++q) sum += c[q];
      y_row[i] += static_cast<T>(scale * sum);
    }
  }
}

template <typename T>
void ScreeningTerm::add_row(
    std::int64_t row, int begin, int end, const std::array<const T*, 9>& x_rows, T* y_row) const {
  const int nx = geometry_.dims.x();
  for (std::int64_t e = row_begin_[row]; e < row_begin_[row + 1]; ++e) {
    const Run& run = runs_[e];
    const int i0 = std::max(run.begin, begin), i1 = std::min(run.end, end);
    const float* c = coefficients_.data() + run.coefficients + 27 * (i0 - run.begin);
    if (run.interior) {
      // Every neighbour inside the grid: a fixed 27-term sum per node, three
      // neighbours along x from each of the 9 rows.
      const std::array<const T*, 9> r = x_rows;
      for (int i = i0; i < i1; ++i, c += 27) {
        T sum = 0;
        for (int q = 0; q < 9; ++q) {
          const T* p = r[q] + (i - 1);
          sum += static_cast<T>(c[3 * q]) * p[0] + static_cast<T>(c[3 * q + 1]) * p[1] +
                 static_cast<T>(c[3 * q + 2]) * p[2];
        }
        y_row[i] += sum;
      }
      continue;
    }
    for (int i = i0; i < i1; ++i, c += 27) {
      T sum = 0;
      for (int q = 0; q < 27; ++q) {
        const int ii = i + q % 3 - 1;
        // Neighbours outside the grid have zero coefficients: skip them.
        if (x_rows[q / 3] && ii >= 0 && ii < nx) sum += static_cast<T>(c[q]) * x_rows[q / 3][ii];
      }
      y_row[i] += sum;
    }
  }
}

}  // namespace hos::recon
