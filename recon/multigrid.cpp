#include "recon/multigrid.h"

#include <cmath>

#include "core/error.h"

namespace hos::recon {
namespace {

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  const std::int64_t n = static_cast<std::int64_t>(a.size());
#pragma omp parallel for reduction(+ : s) schedule(static)
  for (std::int64_t i = 0; i < n; ++i) s += a[i] * b[i];
  return s;
}

// y = a * x + y
void axpy(double a, const std::vector<double>& x, std::vector<double>& y) {
  const std::int64_t n = static_cast<std::int64_t>(x.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) y[i] += a * x[i];
}

constexpr int kCoarsestSweeps = 40;

}  // namespace

MultigridPreconditioner::MultigridPreconditioner(const EnergyOperator& fine, int max_levels,
                                                 int smoothing_steps)
    : smoothing_steps_(smoothing_steps) {
  operators_.push_back(fine);
  while ((max_levels <= 0 || num_levels() < max_levels) &&
         operators_.back().geometry().can_coarsen(3)) {
    operators_.push_back(operators_.back().coarsened());
  }
  for (const auto& op : operators_) {
    std::vector<double> d(op.geometry().num_nodes());
    for (std::int64_t i = 0; i < static_cast<std::int64_t>(d.size()); ++i) {
      d[i] = op.l1_diagonal(i);
    }
    l1_diagonals_.push_back(std::move(d));
  }
}

void MultigridPreconditioner::smooth(int level, const std::vector<double>& b,
                                     std::vector<double>& x, int sweeps) const {
  const EnergyOperator& op = operators_[level];
  const auto& diag = l1_diagonals_[level];
  std::vector<double> ax;
  const std::int64_t n = static_cast<std::int64_t>(x.size());
  for (int s = 0; s < sweeps; ++s) {
    op.apply(x, ax);
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) x[i] += (b[i] - ax[i]) / diag[i];
  }
}

void MultigridPreconditioner::v_cycle(int level, const std::vector<double>& b,
                                      std::vector<double>& x) const {
  x.assign(b.size(), 0.0);
  if (level == num_levels() - 1) {
    smooth(level, b, x, kCoarsestSweeps);
    return;
  }
  smooth(level, b, x, smoothing_steps_);
  const EnergyOperator& op = operators_[level];
  std::vector<double> r;
  op.apply(x, r);
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = b[i] - r[i];
  std::vector<double> rc, ec;
  restrict_to_coarse(op.geometry(), r, operators_[level + 1].geometry(), rc);
  v_cycle(level + 1, rc, ec);
  prolongate_add(operators_[level + 1].geometry(), ec, op.geometry(), x);
  smooth(level, b, x, smoothing_steps_);
}

void MultigridPreconditioner::apply(const std::vector<double>& r, std::vector<double>& z) const {
  v_cycle(0, r, z);
}

SolveReport solve_linear_system(const EnergyOperator& op, const std::vector<double>& b,
                                std::vector<double>& x, const SolverOptions& options,
                                Reporter& reporter) {
  SolveReport report;
  const std::size_t n = b.size();
  x.resize(n, 0.0);
  const MultigridPreconditioner multigrid(op, options.multigrid ? options.max_levels : 1,
                                          options.smoothing_steps);
  report.levels = multigrid.num_levels();
  const auto precondition = [&](const std::vector<double>& r, std::vector<double>& z) {
    if (options.multigrid) {
      multigrid.apply(r, z);
    } else {
      z.resize(n);
      for (std::size_t i = 0; i < n; ++i) z[i] = r[i] / op.l1_diagonal(static_cast<std::int64_t>(i));
    }
  };

  const double b_norm = std::sqrt(dot(b, b));
  if (!std::isfinite(b_norm)) throw NumericalError("recon", "right-hand side is not finite");
  if (b_norm == 0.0) {
    x.assign(n, 0.0);
    report.relative_residual = 0.0;
    report.converged = true;
    return report;
  }
  std::vector<double> r, z, p, ap;
  op.apply(x, r);
  for (std::size_t i = 0; i < n; ++i) r[i] = b[i] - r[i];
  precondition(r, z);
  p = z;
  double rz = dot(r, z);
  report.relative_residual = std::sqrt(dot(r, r)) / b_norm;
  for (int it = 0; it < options.max_iterations && report.relative_residual > options.tolerance;
       ++it) {
    reporter.throw_if_cancelled();
    op.apply(p, ap);
    const double pap = dot(p, ap);
    if (!(pap > 0.0) || !std::isfinite(pap)) {
      throw NumericalError("recon", "conjugate gradients lost positive definiteness (p'Ap = " +
                                        std::to_string(pap) + ")");
    }
    const double alpha = rz / pap;
    axpy(alpha, p, x);
    axpy(-alpha, ap, r);
    report.relative_residual = std::sqrt(dot(r, r)) / b_norm;
    report.residual_history.push_back(report.relative_residual);
    report.iterations = it + 1;
    if (!std::isfinite(report.relative_residual)) {
      throw NumericalError("recon", "the solver diverged (residual is not finite)");
    }
    reporter.debug(format_message("recon: CG iteration ", it + 1, " relative residual ",
                                  report.relative_residual));
    if (report.relative_residual <= options.tolerance) break;
    precondition(r, z);
    const double rz_new = dot(r, z);
    const double beta = rz_new / rz;
    rz = rz_new;
    const std::int64_t nn = static_cast<std::int64_t>(n);
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < nn; ++i) p[i] = z[i] + beta * p[i];
  }
  report.converged = report.relative_residual <= options.tolerance;
  return report;
}

}  // namespace hos::recon
