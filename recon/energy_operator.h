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
#include <vector>

#include "recon/grid.h"
#include "recon/recon_options.h"

namespace hos::recon {

// A constant-coefficient stencil: offsets (within +-2) and coefficients.
struct Stencil {
  std::vector<Eigen::Vector3i> offsets;
  std::vector<double> coefficients;
  double center() const;
  double abs_sum() const;
};

// The stencil of -Lap + 2 hessian_weight H for the energy on spacing h
// (energy (2) gives just -Lap; its TV part is per-node).
Stencil energy_stencil(SmoothnessEnergy energy, double spacing, double hessian_weight);

// Optional screening term weight * sum_i (f(p_i) - target)^2 over the samples
// (f(p_i) trilinear): it pins the level set to the samples where orientations
// are too coarse to place it (one orientation per scan). On coarse multigrid
// levels it is approximated by its diagonal (the splatted sample density).
struct Screening {
  std::vector<std::int64_t> corner;   // per sample: node index of its cell's lower corner
  std::vector<std::array<float, 8>> weights;  // trilinear weights of the 8 corners
  double weight = 0.0;
};

class EnergyOperator {
 public:
  // tv_node_weights: empty, or one weight per node (energy (2)), scaled by tv_weight.
  EnergyOperator(const GridGeometry& geometry, SmoothnessEnergy energy, double hessian_weight,
                 std::vector<double> tv_node_weights = {}, double tv_weight = 0.0);

  const GridGeometry& geometry() const { return geometry_; }
  // Adds the screening term (finest level); see Screening.
  void set_screening(const Screening* screening);
  // y = A x.
  void apply(const std::vector<double>& x, std::vector<double>& y) const;
  // Per-node l1 row sums (>= |a_ii| + sum |a_ij|): the l1-Jacobi smoother.
  double l1_diagonal(std::int64_t node) const;
  // The same energy rediscretized on the coarsened grid (weights restricted).
  EnergyOperator coarsened() const;

 private:
  GridGeometry geometry_;
  SmoothnessEnergy energy_;
  double hessian_weight_;
  Stencil stencil_;
  std::vector<std::int64_t> linear_offsets_;
  std::vector<double> tv_node_weights_;
  double tv_weight_;
  const Screening* screening_ = nullptr;
  std::vector<double> screening_diagonal_;  // weight * density per node
  double stencil_abs_sum_;
};

// Restriction (full weighting, the transpose of prolongation divided by 8) and
// trilinear prolongation between a grid and its coarsened grid.
void restrict_to_coarse(const GridGeometry& fine, const std::vector<double>& r,
                        const GridGeometry& coarse, std::vector<double>& rc);
void prolongate_add(const GridGeometry& coarse, const std::vector<double>& ec,
                    const GridGeometry& fine, std::vector<double>& x);

}  // namespace hos::recon
