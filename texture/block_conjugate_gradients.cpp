#include "texture/block_conjugate_gradients.h"

#include <algorithm>
#include <limits>
#include <vector>

namespace hos::texture {
namespace {

// The three columns side by side: a row's three values share a cache line,
// so the matrix product's gather reads each neighbour once.
using Rows3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

// Rows go in blocks of this many, the blocks in parallel. Each block sums its
// own part of a dot product and the parts are added in block order, so the
// solution does not depend on the number of threads.
constexpr Eigen::Index kBlockRows = 4096;

// Calls part(begin, end) for every block of the rows [0, n) and returns the
// sum, in block order, of what the calls return (Eigen arrays).
template <typename Sums, typename Part>
Sums sum_over_blocks(Eigen::Index n, Part&& part) {
  const int blocks = static_cast<int>((n + kBlockRows - 1) / kBlockRows);
  std::vector<Sums> parts(blocks);
#pragma omp parallel for schedule(static)
  for (int b = 0; b < blocks; ++b) parts[b] = part(b * kBlockRows, std::min(n, (b + 1) * kBlockRows));
  Sums total = Sums::Zero();
  for (const Sums& sums : parts) total += sums;
  return total;
}

// AP = A P for a symmetric A (its columns are its rows: one pass over the
// matrix serves the three columns); returns each column's dot product of P
// with AP, which the step length needs.
Eigen::Array3d multiply_symmetric(const Eigen::SparseMatrix<double>& A, const Rows3& P, Rows3& AP) {
  return sum_over_blocks<Eigen::Array3d>(A.outerSize(), [&](Eigen::Index begin, Eigen::Index end) {
    Eigen::Array3d dots = Eigen::Array3d::Zero();
    for (Eigen::Index j = begin; j < end; ++j) {
      Eigen::Array3d sum = Eigen::Array3d::Zero();
      for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
        sum += it.value() * P.row(it.index()).transpose().array();
      }
      AP.row(j) = sum.transpose();
      dots += P.row(j).transpose().array() * sum;
    }
    return dots;
  });
}

}  // namespace

int block_conjugate_gradients(const Eigen::SparseMatrix<double>& A,
                              const Eigen::MatrixX3d& B,
                              double tolerance,
                              int max_iterations,
                              Eigen::MatrixX3d& X) {
  const Eigen::Index n = B.rows();
  const Eigen::VectorXd inverse_diagonal = A.diagonal().unaryExpr([](double d) { return d != 0.0 ? 1.0 / d : 1.0; });
  const double* d = inverse_diagonal.data();
  Rows3 x = Rows3::Zero(n, 3), r = B, p = inverse_diagonal.asDiagonal() * B, ap(n, 3);
  Eigen::Array3d threshold = tolerance * tolerance * B.colwise().squaredNorm().transpose().array();
  threshold = threshold.cwiseMax(std::numeric_limits<double>::min());
  Eigen::Array3d rz = r.cwiseProduct(p).colwise().sum().transpose().array();
  // A column takes steps while it is active (alpha its step length, beta
  // the weight of its previous direction); a converged one keeps its x.
  Eigen::Array<bool, 3, 1> active = r.colwise().squaredNorm().transpose().array() >= threshold;
  int iterations = 0;
  for (; iterations < max_iterations && active.any(); ++iterations) {
    const Eigen::Array3d p_ap = multiply_symmetric(A, p, ap).max(std::numeric_limits<double>::min());
    const Eigen::Array3d alpha = active.select(rz / p_ap, 0.0);
    // x += alpha p, r -= alpha ap, and r.r and r.z (z = inverse_diagonal r),
    // the three columns in one pass.
    using RrRz = Eigen::Array<double, 6, 1>;
    const RrRz sums = sum_over_blocks<RrRz>(n, [&](Eigen::Index begin, Eigen::Index end) {
      RrRz part = RrRz::Zero();
      for (Eigen::Index i = begin; i < end; ++i) {
        for (int c = 0; c < 3; ++c) {
          x(i, c) += alpha[c] * p(i, c);
          r(i, c) -= alpha[c] * ap(i, c);
          part[c] += r(i, c) * r(i, c);
          part[3 + c] += r(i, c) * (d[i] * r(i, c));
        }
      }
      return part;
    });
    const Eigen::Array3d rr = sums.head<3>(), rz_new = sums.tail<3>();
    active = active && rr >= threshold;
    // p = z + beta p for the columns still active (zero for the others).
    const Eigen::Array3d z_weight = active.cast<double>(), beta = active.select(rz_new / rz, 0.0);
#pragma omp parallel for schedule(static)
    for (Eigen::Index i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) p(i, c) = z_weight[c] * d[i] * r(i, c) + beta[c] * p(i, c);
    }
    rz = active.select(rz_new, rz);
  }
  X = x;
  return iterations;
}

}  // namespace hos::texture
