// Solving A x = b for the energy operators: conjugate gradients preconditioned
// by one symmetric multigrid V-cycle (paper sec. 4.3 used three levels of
// Gauss-Seidel as a cascade; a V-cycle inside CG converges to a stated residual
// in a number of iterations that hardly grows with the grid).
//
// Smoother: l1-Jacobi (x += r / sum_j |a_ij|), convergent for any symmetric
// positive definite operator including the fourth-order ones, parallel, and
// symmetric, so the V-cycle is a valid CG preconditioner.
#pragma once

#include <string>
#include <vector>

#include "core/reporter.h"
#include "recon/energy_operator.h"

namespace hos::recon {

struct SolveReport {
  int iterations = 0;
  int levels = 1;
  double relative_residual = 1.0;  // ||b - A x|| / ||b|| at the end
  bool converged = false;
  std::vector<double> residual_history;  // relative residual after each iteration
  double seconds_setup = 0.0;       // building the multigrid levels
  double seconds_iterations = 0.0;  // the CG iterations
};

// The V-cycle runs in single precision (the outer CG keeps double vectors and
// the exact operator): a preconditioner only needs to be an approximate
// inverse, and float halves the memory traffic of every sweep. Its rounding
// makes it slightly nonlinear, which flexible CG (see solve_linear_system)
// tolerates. apply() uses internal work arrays, so one preconditioner must not
// be applied from two threads at once.
class MultigridPreconditioner {
 public:
  // Builds up to max_levels levels (0 = while every axis keeps >= 3 nodes).
  MultigridPreconditioner(const EnergyOperator& fine, int max_levels, int smoothing_steps);
  int num_levels() const { return static_cast<int>(levels_.size()); }
  // z = M^-1 r by one V-cycle from a zero initial guess, on the active nodes
  // of the operator (arrays in the layout of its active nodes; z is not
  // written elsewhere).
  void apply(const double* r, double* z) const;

 private:
  struct Level {
    EnergyOperator op;
    ZeroedArray<float> inv_l1;     // 1 / l1 row sums
    mutable ZeroedArray<float> b, x, scratch;
  };
  // Levels_[level].x = approximately A^-1 levels_[level].b.
  void v_cycle(int level) const;
  // Sweeps of l1-Jacobi on a level; from_zero: x starts at zero.
  void smooth(const Level& l, int sweeps, bool from_zero) const;

  std::vector<Level> levels_;
  int smoothing_steps_;
};

// Preconditioned CG from the initial guess in x. Throws NumericalError if a
// NaN or Inf appears. Logs the residual every few iterations at debug level.
SolveReport solve_linear_system(const EnergyOperator& op, const std::vector<double>& b,
                                std::vector<double>& x, const SolverOptions& options,
                                Reporter& reporter);

}  // namespace hos::recon
