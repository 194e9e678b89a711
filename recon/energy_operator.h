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
#include "recon/screening_term.h"
#include "recon/stencil.h"

namespace hos::recon {

class EnergyOperator {
 public:
  // tv_node_weights: empty, or one weight per node (energy (2)), scaled by tv_weight.
  EnergyOperator(const GridGeometry& geometry,
                 SmoothnessEnergy energy,
                 double hessian_weight,
                 std::vector<double> tv_node_weights = {},
                 double tv_weight = 0.0);

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
  // The smoothers' steps, with l1 the per-node l1 row sums (>= |a_ii| +
  // sum |a_ij|) of every term, computed on the fly rather than stored (an
  // array as large as x on every multigrid level otherwise).
  // One l1-Jacobi sweep: out = x + (b - A x) / l1 (out must not alias x).
  template <typename T>
  void jacobi(const T* b, const T* x, T* out) const;
  // One step of a polynomial smoother: step = keep * step + a (b - A x) / l1
  // (step must not alias x or b; with keep 0 it is only written).
  template <typename T>
  void smoothing_step(const T* b, const T* x, double keep, double a, T* step) const;
  // out = a * in / l1, no operator application (out must not alias in);
  // copy, unless null, receives the same values in the same pass.
  template <typename T>
  void scale_by_inverse_l1(const T* in, double a, T* out, T* copy = nullptr) const;
  // The l1 row sums themselves, for the active nodes of an array in the
  // layout of active().
  template <typename T>
  void l1_diagonals(T* l1) const;
  // The same energy rediscretized on the coarsened grid (weights restricted,
  // screening rediscretised, active nodes coarsened).
  EnergyOperator coarsened() const;

 private:
  // Calls span_fn(start, begin, end, A x on that row) for every span of
  // active nodes, in parallel: node i of the span is stored at start + i, and
  // (A x)[i] is valid for begin <= i < end.
  // With kWithL1, span_fn also gets the l1 row sums of the span's nodes
  // (span_fn(start, begin, end, ax, l1), l1 indexed like ax).
  template <bool kWithL1 = false, typename T, typename SpanFn>
  void for_each_span(const T* x, SpanFn&& span_fn) const;
  // row[i] += the total-variation term's row of node i of the span applied
  // to x (storage index of node i: start + i).
  template <typename T>
  void add_total_variation(const NodeSpan& span, std::int64_t start, const T* x, T* row) const;
  // l1_row[i] = the l1 row sum of node i of the span, begin <= i < end.
  template <typename T>
  void l1_row(const NodeSpan& span, T* l1_row) const;
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

}  // namespace hos::recon
