// The linear operator of the Euler-Lagrange equation of the energy
//   E(f) = 1/2 sum |grad f - F|^2 + lambda_h E_s(f)
// on the grid, applied matrix-free:
//   A f = -Lap f + 2 lambda_h H f            energies (1), (3), (4)
//   A f = -Lap f - lambda_tv div(w grad f)   energy (2), one reweighting step
// where H = sum_k c_k D_k^T D_k over the derivative stencils of paper eq. (9)
// (fxx, fyy, fzz with weight 1, fxy, fxz, fyz with weight 2 for eq. (4)) and w
// are per-node weights 1 / |grad f| of the iteratively reweighted TV.
// Nodes outside the grid are zero (Dirichlet), so A is symmetric positive
// definite: the null space of constants and linear functions is removed.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "recon/active_nodes.h"
#include "recon/grid.h"
#include "recon/recon_options.h"

namespace hos::recon {

// The terms of a stencil that read one neighbour row (dy, dz): x offsets and
// coefficients (offsets lie within +-2, so at most 5).
struct StencilRow {
  int dy = 0, dz = 0, count = 0;
  std::array<int, 5> ox{};
  std::array<double, 5> c{};
};

// A constant-coefficient stencil: offsets (within +-2) and coefficients.
struct Stencil {
  std::vector<Eigen::Vector3i> offsets;
  std::vector<double> coefficients;
  double center() const;
  double abs_sum() const;
  // The terms grouped by the row they read, in order of first appearance.
  std::vector<StencilRow> rows() const;
};

// The stencil of -Lap + 2 hessian_weight H for the energy on spacing h
// (energy (2) gives just -Lap; its TV part is per-node).
Stencil energy_stencil(SmoothnessEnergy energy, double spacing, double hessian_weight);

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
  ScreeningTerm(const GridGeometry& geometry, const std::vector<Eigen::Vector3f>& points,
                double weight);
  bool empty() const { return runs_.empty(); }
  double weight() const { return weight_; }
  // Adds weight * target * S^T 1 (the target's share of the right-hand side).
  void add_target(double target, std::vector<double>& rhs) const;
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
  void add_row(std::int64_t row, int begin, int end, const std::array<const T*, 9>& x_rows,
               T* y_row) const;

 private:
  GridGeometry geometry_;
  double weight_ = 0.0;
  // The touched nodes as runs of consecutive nodes along x (the rows a span
  // meets are found without a search), each node's 27 coefficients (offsets
  // (-1..1)^3, x fastest) contiguous.
  struct Run {
    int j, k, begin, end;     // grid row and nodes begin <= i < end
    std::int64_t coefficients;  // index of the run's first coefficient
    bool interior;            // all 27 neighbours of every node inside the grid
  };
  std::vector<Run> runs_;
  std::vector<std::int64_t> row_begin_;  // per grid row (j, k): first run
  std::vector<float> coefficients_;
  std::int64_t num_nodes_ = 0;
  mutable std::shared_ptr<const ScreeningTerm> coarser_;
};

class EnergyOperator {
 public:
  // tv_node_weights: empty, or one weight per node (energy (2)), scaled by tv_weight.
  EnergyOperator(const GridGeometry& geometry, SmoothnessEnergy energy, double hessian_weight,
                 std::vector<double> tv_node_weights = {}, double tv_weight = 0.0);

  const GridGeometry& geometry() const { return geometry_; }
  // The nodes whose rows apply, residual and jacobi compute (every node by
  // default), and the layout of the raw arrays below (active().storage_size()
  // values each). Restricted to a band, the operator is the band's principal
  // submatrix for the unknowns and couples them to the fixed values in the
  // band's halo: residual(b, x) reads x at every stored node and writes only
  // active nodes. The total-variation term needs the whole grid.
  const ActiveNodes& active() const { return *active_; }
  void set_active(std::shared_ptr<const ActiveNodes> active);
  // Adds the screening term over these samples (kept for the coarse levels).
  void set_screening(std::shared_ptr<const std::vector<Eigen::Vector3f>> points, double weight);
  const ScreeningTerm& screening() const { return *screening_; }
  void scale_screening(double factor);
  // y = A x.
  void apply(const std::vector<double>& x, std::vector<double>& y) const;
  // The same on raw arrays in the layout of active() (float for the preconditioner).
  template <typename T>
  void apply(const T* x, T* y) const;
  // r = b - A x.
  template <typename T>
  void residual(const T* b, const T* x, T* r) const;
  // One l1-Jacobi sweep: out = x + (b - A x) / l1 (out must not alias x).
  template <typename T>
  void jacobi(const T* b, const T* x, const T* inv_l1, T* out) const;
  // Per-node l1 row sums (>= |a_ii| + sum |a_ij|) of every term: the l1-Jacobi smoother.
  // Written for the active nodes of an array in the layout of active().
  template <typename T>
  void l1_diagonals(T* l1) const;
  // The same energy rediscretized on the coarsened grid (weights restricted,
  // screening rediscretised, active nodes coarsened).
  EnergyOperator coarsened() const;

 private:
  // Calls span_fn(start, begin, end, A x on that row) for every span of
  // active nodes, in parallel: node i of the span is stored at start + i, and
  // (A x)[i] is valid for begin <= i < end.
  template <typename T, typename SpanFn>
  void for_each_span(const T* x, SpanFn&& span_fn) const;
  // The l1 row sum of one node without the screening term.
  double l1_diagonal(std::int64_t node) const;

  GridGeometry geometry_;
  SmoothnessEnergy energy_;
  double hessian_weight_;
  Stencil stencil_;
  std::vector<StencilRow> stencil_rows_;  // stencil_.rows()
  std::vector<double> tv_node_weights_;
  double tv_weight_;
  std::shared_ptr<const std::vector<Eigen::Vector3f>> screening_points_;
  std::shared_ptr<const ScreeningTerm> screening_;  // shared by copies of the operator
  double stencil_abs_sum_;
  std::shared_ptr<const ActiveNodes> active_;
};

// Restriction (full weighting, the transpose of prolongation divided by 8) and
// trilinear prolongation between a grid and its coarsened grid. The raw-array
// versions take each array in the layout of its grid's nodes and write only
// the active nodes of the output (restriction: coarse_active, prolongation:
// fine_active), so a banded hierarchy keeps zeros outside its bands and the
// pair stays transposed. Values that the input's layout does not store are zero.
void restrict_to_coarse(const GridGeometry& fine, const std::vector<double>& r,
                        const GridGeometry& coarse, std::vector<double>& rc);
void prolongate_add(const GridGeometry& coarse, const std::vector<double>& ec,
                    const GridGeometry& fine, std::vector<double>& x);
template <typename T>
void restrict_to_coarse(const GridGeometry& fine, const ActiveNodes& fine_nodes, const T* r,
                        const GridGeometry& coarse, const ActiveNodes& coarse_active, T* rc);
template <typename T>
void prolongate_add(const GridGeometry& coarse, const ActiveNodes& coarse_nodes, const T* ec,
                    const GridGeometry& fine, const ActiveNodes& fine_active, T* x);
// The same from a whole coarse grid to every node a fine layout stores (its
// active nodes and halo): starts a banded solve without a grid-sized array.
void prolongate_add_to_stored(const GridGeometry& coarse, const std::vector<double>& ec,
                              const ActiveNodes& fine_nodes, double* x);

}  // namespace hos::recon
