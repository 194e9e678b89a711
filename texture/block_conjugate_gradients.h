// Conjugate gradients for a symmetric positive definite sparse matrix and
// three right-hand sides at once (one pass over the matrix per iteration
// serves all three), with the diagonal preconditioner.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace hos::texture {

// Solves A X = B from X = 0 with each column stopping on its own when its
// residual falls below tolerance times its right-hand side's norm: the steps
// and stopping rule of Eigen's ConjugateGradient with a diagonal
// preconditioner, column by column. A must be symmetric (only its columns are
// read). Returns the most iterations of a column.
int block_conjugate_gradients(const Eigen::SparseMatrix<double>& A,
                              const Eigen::MatrixX3d& B,
                              double tolerance,
                              int max_iterations,
                              Eigen::MatrixX3d& X);

}  // namespace hos::texture
