#include "texture/block_conjugate_gradients.h"

#include <array>
#include <limits>

namespace hos::texture {
namespace {

// Y = A X for a symmetric A: its columns are its rows. One pass over the
// matrix serves the three channels.
void multiply_symmetric(const Eigen::SparseMatrix<double>& A, const Eigen::MatrixX3d& X, Eigen::MatrixX3d& Y) {
  const double *x0 = X.col(0).data(), *x1 = X.col(1).data(), *x2 = X.col(2).data();
  double *y0 = Y.col(0).data(), *y1 = Y.col(1).data(), *y2 = Y.col(2).data();
  for (int j = 0; j < static_cast<int>(A.outerSize()); ++j) {
    double s0 = 0.0, s1 = 0.0, s2 = 0.0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
      const double v = it.value();
      const Eigen::Index i = it.index();
      s0 += v * x0[i];
      s1 += v * x1[i];
      s2 += v * x2[i];
    }
    y0[j] = s0;
    y1[j] = s1;
    y2[j] = s2;
  }
}

}  // namespace

int block_conjugate_gradients(const Eigen::SparseMatrix<double>& A,
                              const Eigen::MatrixX3d& B,
                              double tolerance,
                              int max_iterations,
                              Eigen::MatrixX3d& X) {
  const Eigen::Index n = B.rows();
  const Eigen::VectorXd inverse_diagonal = A.diagonal().unaryExpr([](double d) { return d != 0.0 ? 1.0 / d : 1.0; });
  X.setZero(n, 3);
  Eigen::MatrixX3d R = B, Z = inverse_diagonal.asDiagonal() * R, P = Z, AP(n, 3);
  Eigen::RowVector3d threshold = tolerance * tolerance * B.colwise().squaredNorm();
  threshold = threshold.cwiseMax(std::numeric_limits<double>::min());
  Eigen::RowVector3d rz = (R.cwiseProduct(Z)).colwise().sum();
  std::array<bool, 3> active{};
  for (int c = 0; c < 3; ++c) active[c] = R.col(c).squaredNorm() >= threshold[c];
  int iterations = 0;
  for (; iterations < max_iterations && (active[0] || active[1] || active[2]); ++iterations) {
    multiply_symmetric(A, P, AP);
    for (int c = 0; c < 3; ++c) {
      if (!active[c]) continue;
      const double alpha = rz[c] / P.col(c).dot(AP.col(c));
      X.col(c) += alpha * P.col(c);
      R.col(c) -= alpha * AP.col(c);
      if (R.col(c).squaredNorm() < threshold[c]) {
        active[c] = false;
        continue;
      }
      Z.col(c) = inverse_diagonal.cwiseProduct(R.col(c));
      const double rz_new = R.col(c).dot(Z.col(c));
      P.col(c) = Z.col(c) + (rz_new / rz[c]) * P.col(c);
      rz[c] = rz_new;
    }
  }
  return iterations;
}

}  // namespace hos::texture
