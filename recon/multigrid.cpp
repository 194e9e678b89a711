#include "recon/multigrid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/error.h"
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

// y = a * x + y on the active nodes.
void axpy(const EnergyOperator& op, double a, const double* x, double* y) {
  for_each_active_range(op.active(), [&](std::int64_t first, std::int64_t last) {
    for (std::int64_t i = first; i < last; ++i) y[i] += a * x[i];
  });
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
  for (auto& op : ops) {
    const std::size_t n = static_cast<std::size_t>(op.active().storage_size());
    Level level{std::move(op),         ZeroedArray<float>(n), ZeroedArray<float>(n),
                ZeroedArray<float>(n), ZeroedArray<float>(n), ZeroedArray<float>(n)};
    level.op.l1_diagonals(level.inv_l1.data());
    for_each_active_range(level.op.active(), [&](std::int64_t first, std::int64_t last) {
      for (std::int64_t i = first; i < last; ++i) level.inv_l1[i] = 1.0f / level.inv_l1[i];
    });
    levels_.push_back(std::move(level));
  }
}

void MultigridPreconditioner::smooth(const Level& l, int degree, bool from_zero) const {
  // The Chebyshev polynomial of this degree in M A, M = diag(inv_l1), that is
  // smallest over [1 / kChebyshevRatio, 1]: the eigenvalues of M A lie in
  // (0, 1] for l1 row sums, and the upper part of the spectrum is what the
  // coarse levels cannot correct. Three-term recurrence, one residual per
  // step after the first.
  const double upper = 1.0, lower = upper / kChebyshevRatio;
  const double theta = 0.5 * (upper + lower), delta = 0.5 * (upper - lower), sigma = theta / delta;
  double rho = 1.0 / sigma;
  const ActiveNodes& active = l.op.active();
  for (int s = 0; s < degree; ++s) {
    const float* r = l.b.data();
    if (!(from_zero && s == 0)) {
      l.op.residual(l.b.data(), l.x.data(), l.scratch.data());
      r = l.scratch.data();
    }
    if (s == 0) {
      const float a = static_cast<float>(1.0 / theta);
      for_each_active_range(active, [&](std::int64_t first, std::int64_t last) {
        for (std::int64_t i = first; i < last; ++i) {
          l.step[i] = a * r[i] * l.inv_l1[i];
          l.x[i] = (from_zero ? 0.0f : l.x[i]) + l.step[i];
        }
      });
      continue;
    }
    const double rho_next = 1.0 / (2.0 * sigma - rho);
    const float keep = static_cast<float>(rho_next * rho), a = static_cast<float>(2.0 * rho_next / delta);
    rho = rho_next;
    for_each_active_range(active, [&](std::int64_t first, std::int64_t last) {
      for (std::int64_t i = first; i < last; ++i) {
        l.step[i] = keep * l.step[i] + a * r[i] * l.inv_l1[i];
        l.x[i] += l.step[i];
      }
    });
  }
}

void MultigridPreconditioner::smooth_jacobi(const Level& l, int sweeps, bool from_zero) const {
  int s = 0;
  if (from_zero && sweeps > 0) {
    // The first sweep from x = 0 needs no operator application.
    for_each_active_range(l.op.active(), [&](std::int64_t first, std::int64_t last) {
      for (std::int64_t i = first; i < last; ++i) l.x[i] = l.b[i] * l.inv_l1[i];
    });
    s = 1;
  }
  for (; s < sweeps; ++s) {
    l.op.jacobi(l.b.data(), l.x.data(), l.inv_l1.data(), l.scratch.data());
    l.x.swap(l.scratch);
  }
}

void MultigridPreconditioner::v_cycle(int level) const {
  const Level& l = levels_[level];
  if (level == num_levels() - 1) {
    smooth_jacobi(l, kCoarsestSweeps, true);
    return;
  }
  smooth(l, smoothing_steps_, true);
  l.op.residual(l.b.data(), l.x.data(), l.scratch.data());
  const Level& c = levels_[level + 1];
  restrict_to_coarse(l.op.geometry(), l.op.active(), l.scratch.data(), c.op.geometry(), c.op.active(), c.b.data());
  v_cycle(level + 1);
  prolongate_add(c.op.geometry(), c.op.active(), c.x.data(), l.op.geometry(), l.op.active(), l.x.data());
  smooth(l, smoothing_steps_, false);
}

const float* MultigridPreconditioner::apply(const double* r) const {
  const Level& l = levels_.front();
  for_each_active_range(l.op.active(), [&](std::int64_t first, std::int64_t last) {
    for (std::int64_t i = first; i < last; ++i) l.b[i] = static_cast<float>(r[i]);
  });
  v_cycle(0);
  return l.x.data();
}

namespace {

// solve_linear_system; owned_b, if not null, is b and is freed after the
// first residual.
SolveReport conjugate_gradients(const EnergyOperator& op,
                                const std::vector<double>& b,
                                std::vector<double>* owned_b,
                                std::vector<double>& x,
                                const SolverOptions& options,
                                Reporter& reporter) {
  using Clock = std::chrono::steady_clock;
  const auto seconds_since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  const auto t_setup = Clock::now();
  SolveReport report;
  const std::size_t n = b.size();
  if (static_cast<std::int64_t>(n) != op.active().storage_size()) {
    throw std::invalid_argument("solve_linear_system: the right-hand side has " + std::to_string(n) +
                                " values, the operator's layout " + std::to_string(op.active().storage_size()));
  }
  x.resize(n, 0.0);
  const MultigridPreconditioner multigrid(op, options.multigrid ? options.max_levels : 1, options.smoothing_steps);
  report.levels = multigrid.num_levels();
  ZeroedArray<double> inv_l1, z_jacobi;
  if (!options.multigrid) {
    inv_l1 = ZeroedArray<double>(n);
    z_jacobi = ZeroedArray<double>(n);
    op.l1_diagonals(inv_l1.data());
    for_each_active_range(op.active(), [&](std::int64_t first, std::int64_t last) {
      for (std::int64_t i = first; i < last; ++i) inv_l1[i] = 1.0 / inv_l1[i];
    });
  }
  const auto for_active = [&](auto&& fn) { for_each_active_range(op.active(), fn); };
  // z = M^-1 r: the V-cycle's own single-precision result, or l1-Jacobi's in
  // double; both are read only through z_at.
  const float* z_multigrid = nullptr;
  const auto precondition = [&](const double* r) {
    if (options.multigrid) {
      z_multigrid = multigrid.apply(r);
    } else {
      for_active([&](std::int64_t first, std::int64_t last) {
        for (std::int64_t i = first; i < last; ++i) z_jacobi[i] = r[i] * inv_l1[i];
      });
    }
  };
  const auto z_at = [&](std::int64_t i) { return options.multigrid ? double{z_multigrid[i]} : z_jacobi[i]; };
  const auto dot_rz = [&](const double* r) {
    return options.multigrid ? dot(op, r, z_multigrid) : dot(op, r, z_jacobi.data());
  };

  // The residual is relative to |b| over the rows being solved.
  double b_norm = std::sqrt(dot(op, b.data(), b.data()));
  if (!std::isfinite(b_norm)) throw NumericalError("recon", "right-hand side is not finite");
  if (b_norm == 0.0 && op.active().is_all()) {
    x.assign(n, 0.0);
    report.relative_residual = 0.0;
    report.converged = true;
    return report;
  }
  // Only the active nodes of these are written (and p, zero elsewhere, read
  // around them).
  const ZeroedArray<double> r_values(n), p_values(n), ap_values(n);
  double* const r = r_values.data();
  double* const p = p_values.data();
  double* const ap = ap_values.data();
  report.seconds_setup = seconds_since(t_setup);
  const auto t_iterations = Clock::now();
  op.residual(b.data(), x.data(), r);
  if (owned_b) *owned_b = std::vector<double>{};
  if (b_norm == 0.0) {
    // A band whose rows have no data of their own: only the values held
    // outside drive it, so the first residual sets the scale.
    b_norm = std::sqrt(dot(op, r, r));
    if (b_norm == 0.0) {
      report.relative_residual = 0.0;
      report.converged = true;
      return report;
    }
  }
  precondition(r);
  for_active([&](std::int64_t first, std::int64_t last) {
    for (std::int64_t i = first; i < last; ++i) p[i] = z_at(i);
  });
  double rz = dot_rz(r);
  report.relative_residual = std::sqrt(dot(op, r, r)) / b_norm;
  for (int it = 0; it < options.max_iterations && report.relative_residual > options.tolerance; ++it) {
    reporter.throw_if_cancelled();
    op.apply(p, ap);
    const double pap = dot(op, p, ap);
    if (!(pap > 0.0) || !std::isfinite(pap)) {
      throw NumericalError("recon",
                           "conjugate gradients lost positive definiteness (p'Ap = " + std::to_string(pap) + ")");
    }
    const double alpha = rz / pap;
    axpy(op, alpha, p, x.data());
    axpy(op, -alpha, ap, r);
    report.relative_residual = std::sqrt(dot(op, r, r)) / b_norm;
    report.residual_history.push_back(report.relative_residual);
    report.iterations = it + 1;
    if (!std::isfinite(report.relative_residual)) {
      throw NumericalError("recon", "the solver diverged (residual is not finite)");
    }
    reporter.debug(format_message("recon: CG iteration ", it + 1, " relative residual ", report.relative_residual));
    if (report.relative_residual <= options.tolerance) break;
    // Flexible (Polak-Ribiere) beta = r' (z_new - z_old) / r_old' z_old: it
    // keeps CG convergent with the slightly nonlinear single-precision V-cycle.
    const double r_z_old = dot_rz(r);
    precondition(r);
    const double rz_new = dot_rz(r);
    const double beta = (rz_new - r_z_old) / rz;
    rz = rz_new;
    for_active([&](std::int64_t first, std::int64_t last) {
      for (std::int64_t i = first; i < last; ++i) p[i] = z_at(i) + beta * p[i];
    });
  }
  report.converged = report.relative_residual <= options.tolerance;
  report.seconds_iterations = seconds_since(t_iterations);
  return report;
}

}  // namespace

SolveReport solve_linear_system(const EnergyOperator& op,
                                const std::vector<double>& b,
                                std::vector<double>& x,
                                const SolverOptions& options,
                                Reporter& reporter) {
  return conjugate_gradients(op, b, nullptr, x, options, reporter);
}

SolveReport solve_linear_system(const EnergyOperator& op,
                                std::vector<double>&& b,
                                std::vector<double>& x,
                                const SolverOptions& options,
                                Reporter& reporter) {
  return conjugate_gradients(op, b, &b, x, options, reporter);
}

}  // namespace hos::recon
