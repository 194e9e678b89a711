#include "recon/multigrid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "core/error.h"
#include "core/huge_pages.h"
#include "recon/grid_transfer.h"

namespace hos::recon {
namespace {

// a . b over the active nodes of op (the vectors are zero elsewhere, or, for
// the solution, fixed there).
template <typename A, typename B>
double dot(const EnergyOperator& op, const A* a, const B* b) {
  const std::vector<NodeSpan>& spans = op.active().spans();
  const std::int64_t n = static_cast<std::int64_t>(spans.size());
  double s = 0.0;
#pragma omp parallel for reduction(+ : s) schedule(static) if (worth_threads(op.active().count()))
  for (std::int64_t q = 0; q < n; ++q) {
    const std::int64_t first = spans[q].first, last = first + (spans[q].end - spans[q].begin);
    for (std::int64_t i = first; i < last; ++i) s += static_cast<double>(a[i]) * static_cast<double>(b[i]);
  }
  return s;
}

// The step of a CG iteration, x += alpha p and r -= alpha ap on the active
// nodes, in one pass with the dot products the iteration needs next: r . r
// and r . z (the new r, the z of the last preconditioning). Each sum runs
// over the nodes in the order of dot, so the figures are dot's.
template <typename T, typename Z>
std::pair<double, double> cg_step(
    const EnergyOperator& op, double alpha, const T* p, const T* ap, T* x, T* r, const Z* z) {
  const std::vector<NodeSpan>& spans = op.active().spans();
  const std::int64_t n = static_cast<std::int64_t>(spans.size());
  const T at = static_cast<T>(alpha), minus_at = static_cast<T>(-alpha);
  double rr = 0.0, rz = 0.0;
#pragma omp parallel for reduction(+ : rr, rz) schedule(static) if (worth_threads(op.active().count()))
  for (std::int64_t q = 0; q < n; ++q) {
    const std::int64_t first = spans[q].first, last = first + (spans[q].end - spans[q].begin);
    for (std::int64_t i = first; i < last; ++i) x[i] += at * p[i];
    for (std::int64_t i = first; i < last; ++i) r[i] += minus_at * ap[i];
    for (std::int64_t i = first; i < last; ++i) {
      rr += static_cast<double>(r[i]) * static_cast<double>(r[i]);
      rz += static_cast<double>(r[i]) * static_cast<double>(z[i]);
    }
  }
  return {rr, rz};
}

constexpr int kCoarsestSweeps = 40;
// The smoother damps the eigenvalues of M A in [1 / kChebyshevRatio, 1]
// (bunny at grid 256, degree 2: fine band 9 CG iterations with 10, 10 with
// 20, 11 with 30).
constexpr double kChebyshevRatio = 10.0;

}  // namespace

MultigridPreconditioner::MultigridPreconditioner(const EnergyOperator& fine, int max_levels, int smoothing_steps)
    : smoothing_steps_(smoothing_steps) {
  std::vector<EnergyOperator> ops{fine};
  while ((max_levels <= 0 || static_cast<int>(ops.size()) < max_levels) && ops.back().geometry().can_coarsen(3)) {
    ops.push_back(ops.back().coarsened());
  }
  for (std::size_t i = 0; i < ops.size(); ++i) {
    const std::size_t n = static_cast<std::size_t>(ops[i].active().storage_size());
    // The finest level's b and step come with apply.
    const std::size_t own = i == 0 ? 0 : n;
    Level level{std::move(ops[i]), ZeroedArray<float>(own), ZeroedArray<float>(n), ZeroedArray<float>(own)};
    level.rhs = level.b.data();
    level.work = level.step.data();
    levels_.push_back(std::move(level));
  }
}

void MultigridPreconditioner::smooth(const Level& l, int degree, bool from_zero) const {
  // The Chebyshev polynomial of this degree in M A, M = diag(1 / l1), that
  // is smallest over [1 / kChebyshevRatio, 1]: the eigenvalues of M A lie in
  // (0, 1] for l1 row sums, and the upper part of the spectrum is what the
  // coarse levels cannot correct. Three-term recurrence, one operator
  // application per step after the first.
  const double upper = 1.0, lower = upper / kChebyshevRatio;
  const double theta = 0.5 * (upper + lower), delta = 0.5 * (upper - lower), sigma = theta / delta;
  double rho = 1.0 / sigma;
  const ActiveNodes& active = l.op.active();
  float* const x = l.x.data();
  float* const step = l.work;
  for (int s = 0; s < degree; ++s) {
    if (s == 0 && from_zero) {
      l.op.scale_by_inverse_l1(l.rhs, 1.0 / theta, step, x);
      continue;
    }
    if (s == 0) {
      l.op.smoothing_step(l.rhs, x, 0.0, 1.0 / theta, step);
    } else {
      const double rho_next = 1.0 / (2.0 * sigma - rho);
      l.op.smoothing_step(l.rhs, x, rho_next * rho, 2.0 * rho_next / delta, step);
      rho = rho_next;
    }
    for_each_active_range(active, [&](std::int64_t first, std::int64_t last) {
      for (std::int64_t i = first; i < last; ++i) x[i] += step[i];
    });
  }
}

void MultigridPreconditioner::smooth_jacobi(const Level& l, int sweeps, bool from_zero) const {
  int s = 0;
  if (from_zero && sweeps > 0) {
    // The first sweep from x = 0 needs no operator application.
    l.op.scale_by_inverse_l1(l.rhs, 1.0, l.x.data());
    s = 1;
  }
  for (; s < sweeps; ++s) {
    l.op.jacobi(l.rhs, l.x.data(), l.work);
    for_each_active_range(l.op.active(), [&](std::int64_t first, std::int64_t last) {
      std::copy(l.work + first, l.work + last, l.x.data() + first);
    });
  }
}

void MultigridPreconditioner::v_cycle(int level) const {
  const Level& l = levels_[level];
  if (level == num_levels() - 1) {
    smooth_jacobi(l, kCoarsestSweeps, true);
    return;
  }
  smooth(l, smoothing_steps_, true);
  // The residual in the step's array, which the next smoothing rewrites.
  l.op.residual(l.rhs, l.x.data(), l.work);
  const Level& c = levels_[level + 1];
  restrict_to_coarse(l.op.geometry(), l.op.active(), l.work, c.op.geometry(), c.op.active(), c.b.data());
  v_cycle(level + 1);
  prolongate_add(c.op.geometry(), c.op.active(), c.x.data(), l.op.geometry(), l.op.active(), l.x.data());
  smooth(l, smoothing_steps_, false);
}

const float* MultigridPreconditioner::apply(const double* r) const {
  const Level& l = levels_.front();
  if (l.b.size() == 0) {
    const std::size_t n = l.x.size();
    l.b = ZeroedArray<float>(n);
    l.step = ZeroedArray<float>(n);
  }
  for_each_active_range(l.op.active(), [&](std::int64_t first, std::int64_t last) {
    for (std::int64_t i = first; i < last; ++i) l.b[i] = static_cast<float>(r[i]);
  });
  l.rhs = l.b.data();
  l.work = l.step.data();
  v_cycle(0);
  return l.x.data();
}

const float* MultigridPreconditioner::apply(const float* r, float* work) const {
  const Level& l = levels_.front();
  l.rhs = r;
  l.work = work;
  v_cycle(0);
  return l.x.data();
}

namespace {

// z = M^-1 r for CG: the V-cycle's own single-precision result, or
// l1-Jacobi's; both are read only through z_at.
template <typename Real>
class CgPreconditioner {
 public:
  CgPreconditioner(const EnergyOperator& op, const SolverOptions& options)
      : op_(op),
        use_multigrid_(options.multigrid),
        multigrid_(op, options.multigrid ? options.max_levels : 1, options.smoothing_steps) {
    if (use_multigrid_) return;
    const auto n = static_cast<std::size_t>(op.active().storage_size());
    inv_l1_ = ZeroedArray<Real>(n);
    z_jacobi_ = ZeroedArray<Real>(n);
    op.l1_diagonals(inv_l1_.data());
    for_each_active_range(op.active(), [&](std::int64_t first, std::int64_t last) {
      for (std::int64_t i = first; i < last; ++i) inv_l1_[i] = Real(1) / inv_l1_[i];
    });
  }

  int num_levels() const { return multigrid_.num_levels(); }

  // A float r is read in place by the V-cycle, with `free_work` (unused
  // until the next operator application) lent as the finest smoother step.
  void apply(const Real* r, Real* free_work) {
    if (use_multigrid_) {
      if constexpr (std::is_same_v<Real, float>) {
        z_multigrid_ = multigrid_.apply(r, free_work);
      } else {
        z_multigrid_ = multigrid_.apply(r);
      }
    } else {
      for_each_active_range(op_.active(), [&](std::int64_t first, std::int64_t last) {
        for (std::int64_t i = first; i < last; ++i) z_jacobi_[i] = r[i] * inv_l1_[i];
      });
    }
  }

  Real z_at(std::int64_t i) const { return use_multigrid_ ? Real(z_multigrid_[i]) : z_jacobi_[i]; }

  double dot_rz(const Real* r) const {
    return use_multigrid_ ? dot(op_, r, z_multigrid_) : dot(op_, r, z_jacobi_.data());
  }

  // x += alpha p, r -= alpha Ap; returns r'r and the old r'z.
  std::pair<double, double> step(double alpha, const Real* p, const Real* ap, Real* x, Real* r) const {
    return use_multigrid_ ? cg_step(op_, alpha, p, ap, x, r, z_multigrid_)
                          : cg_step(op_, alpha, p, ap, x, r, z_jacobi_.data());
  }

 private:
  const EnergyOperator& op_;
  bool use_multigrid_;
  MultigridPreconditioner multigrid_;
  ZeroedArray<Real> inv_l1_, z_jacobi_;
  const float* z_multigrid_ = nullptr;
};

// Turns r from b into b - A x and returns the norm the residual is relative
// to (|b| over the rows being solved); 0 when x = 0 already solves it.
template <typename Real>
double initial_residual(const EnergyOperator& op, Real* r, Real* x) {
  double b_norm = std::sqrt(dot(op, r, r));
  if (!std::isfinite(b_norm)) throw NumericalError("recon", "right-hand side is not finite");
  if (b_norm == 0.0 && op.active().is_all()) {
    for_each_active_range(op.active(),
                          [&](std::int64_t first, std::int64_t last) { std::fill(x + first, x + last, Real(0)); });
    return 0.0;
  }
  // r = b - A x in b's storage (each row reads x only).
  op.residual(r, x, r);
  // A band whose rows have no data of their own: only the values held
  // outside drive it, so the first residual sets the scale.
  if (b_norm == 0.0) b_norm = std::sqrt(dot(op, r, r));
  return b_norm;
}

// p = z + beta p over the active rows.
template <typename Real>
void update_direction(const EnergyOperator& op, const CgPreconditioner<Real>& m, double beta, Real* p) {
  for_each_active_range(op.active(), [&](std::int64_t first, std::int64_t last) {
    for (std::int64_t i = first; i < last; ++i) p[i] = m.z_at(i) + static_cast<Real>(beta) * p[i];
  });
}

// Flexible preconditioned CG on raw arrays of the operator's layout: r holds
// b on entry and the residual on return, x the initial guess and the result.
template <typename Real>
SolveReport conjugate_gradients(
    const EnergyOperator& op, Real* r, Real* x, const SolverOptions& options, Reporter& reporter) {
  using Clock = std::chrono::steady_clock;
  const auto seconds_since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  const auto t_setup = Clock::now();
  SolveReport report;
  const double b_norm = initial_residual(op, r, x);
  if (b_norm == 0.0) {
    report.relative_residual = 0.0;
    report.converged = true;
    return report;
  }
  CgPreconditioner<Real> m(op, options);
  report.levels = m.num_levels();
  // Only the active nodes of these are written (and p, zero elsewhere, read
  // around them).
  const auto n = static_cast<std::size_t>(op.active().storage_size());
  const ZeroedArray<Real> p_values(n), ap_values(n);
  Real* const p = p_values.data();
  Real* const ap = ap_values.data();
  report.seconds_setup = seconds_since(t_setup);
  const auto t_iterations = Clock::now();

  m.apply(r, ap);
  update_direction(op, m, 0.0, p);
  double rz = m.dot_rz(r);
  report.relative_residual = std::sqrt(dot(op, r, r)) / b_norm;
  for (int it = 0; it < options.max_iterations && report.relative_residual > options.tolerance; ++it) {
    reporter.throw_if_cancelled();
    op.apply(p, ap);
    const double pap = dot(op, p, ap);
    if (!(pap > 0.0) || !std::isfinite(pap)) {
      throw NumericalError("recon",
                           "conjugate gradients lost positive definiteness (p'Ap = " + std::to_string(pap) + ")");
    }
    const auto [rr, r_z_old] = m.step(rz / pap, p, ap, x, r);
    report.relative_residual = std::sqrt(rr) / b_norm;
    report.residual_history.push_back(report.relative_residual);
    report.iterations = it + 1;
    if (!std::isfinite(report.relative_residual)) {
      throw NumericalError("recon", "the solver diverged (residual is not finite)");
    }
    reporter.debug(format_message("recon: CG iteration ", it + 1, " relative residual ", report.relative_residual));
    if (report.relative_residual <= options.tolerance) break;
    // Flexible (Polak-Ribiere) beta = r' (z_new - z_old) / r_old' z_old: it
    // keeps CG convergent with the slightly nonlinear single-precision V-cycle.
    m.apply(r, ap);
    const double rz_new = m.dot_rz(r);
    const double beta = (rz_new - r_z_old) / rz;
    rz = rz_new;
    update_direction(op, m, beta, p);
  }
  report.converged = report.relative_residual <= options.tolerance;
  report.seconds_iterations = seconds_since(t_iterations);
  return report;
}

void check_layout(const EnergyOperator& op, std::size_t n) {
  if (static_cast<std::int64_t>(n) != op.active().storage_size()) {
    throw std::invalid_argument("solve_linear_system: the right-hand side has " + std::to_string(n) +
                                " values, the operator's layout " + std::to_string(op.active().storage_size()));
  }
}

// CG in single precision: x and b are converted (b freed first when owned),
// and x returns in double.
SolveReport solve_in_single_precision(const EnergyOperator& op,
                                      const std::vector<double>& b,
                                      std::vector<double>* owned_b,
                                      std::vector<double>& x,
                                      const SolverOptions& options,
                                      Reporter& reporter) {
  // Each double array is freed as soon as its copy exists.
  const std::size_t n = b.size();
  ZeroedArray<float> xf(n);
  std::copy(x.begin(), x.end(), xf.data());
  x = std::vector<double>{};
  ZeroedArray<float> rf(n);
  std::copy(b.begin(), b.end(), rf.data());
  if (owned_b) *owned_b = std::vector<double>{};
  // The freed double arrays leave holes that the solver's arrays may not
  // fill exactly: their pages go back before those are made.
  release_freed_memory();
  SolveReport report = conjugate_gradients(op, rf.data(), xf.data(), options, reporter);
  rf = ZeroedArray<float>{};
  x.assign(xf.data(), xf.data() + n);
  return report;
}

}  // namespace

SolveReport solve_linear_system(const EnergyOperator& op,
                                const std::vector<double>& b,
                                std::vector<double>& x,
                                const SolverOptions& options,
                                Reporter& reporter,
                                VectorPrecision precision) {
  check_layout(op, b.size());
  x.resize(b.size(), 0.0);
  if (precision == VectorPrecision::kSingle) return solve_in_single_precision(op, b, nullptr, x, options, reporter);
  std::vector<double> r = b;
  return conjugate_gradients(op, r.data(), x.data(), options, reporter);
}

SolveReport solve_linear_system(const EnergyOperator& op,
                                std::vector<double>&& b,
                                std::vector<double>& x,
                                const SolverOptions& options,
                                Reporter& reporter,
                                VectorPrecision precision) {
  check_layout(op, b.size());
  x.resize(b.size(), 0.0);
  if (precision == VectorPrecision::kSingle) return solve_in_single_precision(op, b, &b, x, options, reporter);
  // b's storage becomes the residual and is freed on return.
  std::vector<double> r = std::move(b);
  return conjugate_gradients(op, r.data(), x.data(), options, reporter);
}

}  // namespace hos::recon
