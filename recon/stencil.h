// The constant-coefficient stencils of the energies: -Lap + 2 lambda_h H,
// where H = sum_k c_k D_k^T D_k over the derivative stencils of paper eq. (9)
// (fxx, fyy, fzz with weight 1, fxy, fxz, fyz with weight 2 for eq. (4)).
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

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
Stencil energy_stencil(SmoothnessEnergy energy, double h, double hessian_weight);

}  // namespace hos::recon
