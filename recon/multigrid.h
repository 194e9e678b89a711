// Solving A x = b for the energy operators: conjugate gradients preconditioned
// by one symmetric multigrid V-cycle (paper sec. 4.3 used three levels of
// Gauss-Seidel as a cascade; a V-cycle inside CG converges to a stated residual
// in a number of iterations that hardly grows with the grid).
//
// Smoother: a Chebyshev polynomial in M A with M the inverse l1 row sums
// (M = 1 / sum_j |a_ij|): for any symmetric positive definite operator,
// including the fourth-order ones, the eigenvalues of M A lie in (0, 1], so
// the polynomial that is smallest over [1/10, 1] damps the high frequencies
// without an eigenvalue estimate. It is parallel, and the same polynomial
// before and after the coarse correction keeps the V-cycle symmetric, a valid
// CG preconditioner. Against l1-Jacobi with the same number of operator
// applications it cut the bunny's fine-band iterations from 18 to 9-10 and
// fixed the iteration count's growth with the resolution. The coarsest level
// runs 40 sweeps of l1-Jacobi.
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
  double seconds_setup = 0.0;            // building the multigrid levels
  double seconds_iterations = 0.0;       // the CG iterations
};

// The V-cycle runs in single precision (the outer CG keeps the exact
// operator): a preconditioner only needs to be an approximate inverse, and
// float halves the memory traffic of every sweep. Its rounding makes it
// slightly nonlinear, which flexible CG (see solve_linear_system) tolerates.
// Each level keeps three arrays (right-hand side, solution, smoother step);
// the l1 row sums are computed on the fly. apply() uses them as work arrays,
// so one preconditioner must not be applied from two threads at once.
class MultigridPreconditioner {
 public:
  // Builds up to max_levels levels (0 = while every axis keeps >= 3 nodes).
  MultigridPreconditioner(const EnergyOperator& fine, int max_levels, int smoothing_steps);
  int num_levels() const { return static_cast<int>(levels_.size()); }
  // z = M^-1 r by one V-cycle from a zero initial guess, on the active nodes
  // of the operator (arrays in the layout of its active nodes). z is the
  // finest level's own array, valid until the next apply: the V-cycle's
  // result is single precision, so a copy in double would only add memory.
  const float* apply(const double* r) const;
  // The same for a single-precision r, which the finest level reads in
  // place, with `work` (as large as r, overwritten) as its smoother step:
  // two arrays of the finest level fewer.
  const float* apply(const float* r, float* work) const;

 private:
  struct Level {
    EnergyOperator op;
    mutable ZeroedArray<float> b, x, step;  // the finest b and step: see apply
    // The arrays the cycle uses: b and step's, or the finest level's lent ones.
    mutable const float* rhs = nullptr;
    mutable float* work = nullptr;
  };
  // Levels_[level].x = approximately A^-1 levels_[level].rhs.
  void v_cycle(int level) const;
  // Chebyshev smoothing of the given degree (operator applications) on a
  // level; from_zero: x starts at zero.
  void smooth(const Level& l, int degree, bool from_zero) const;
  // Sweeps of l1-Jacobi (the coarsest level).
  void smooth_jacobi(const Level& l, int sweeps, bool from_zero) const;

  std::vector<Level> levels_;
  int smoothing_steps_;
};

// Precision of the conjugate-gradient vectors. Single halves their memory
// (used for the grids that keep only the band, where they are the peak); the
// operator, the dot products and the step lengths stay in double.
enum class VectorPrecision { kDouble, kSingle };

// Preconditioned CG from the initial guess in x. Throws NumericalError if a
// NaN or Inf appears. Logs the residual every few iterations at debug level.
SolveReport solve_linear_system(const EnergyOperator& op,
                                const std::vector<double>& b,
                                std::vector<double>& x,
                                const SolverOptions& options,
                                Reporter& reporter,
                                VectorPrecision precision = VectorPrecision::kDouble);
// The same, with b's storage reused for the residual (CG does not read b
// again): on a large band one array fewer at the peak.
SolveReport solve_linear_system(const EnergyOperator& op,
                                std::vector<double>&& b,
                                std::vector<double>& x,
                                const SolverOptions& options,
                                Reporter& reporter,
                                VectorPrecision precision = VectorPrecision::kDouble);

}  // namespace hos::recon
