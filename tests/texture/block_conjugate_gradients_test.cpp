#include "texture/block_conjugate_gradients.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <random>
#include <vector>

namespace hos::texture {
namespace {

// A symmetric positive definite matrix shaped like the leveling energy's: a
// grid graph's Laplacian with random edge weights plus a small random
// diagonal, so that a column's conjugate gradients take many steps.
Eigen::SparseMatrix<double> random_laplacian(int side, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> weight(0.1, 10.0), shift(1e-3, 1e-2);
  std::vector<Eigen::Triplet<double>> triplets;
  const auto add_edge = [&](int a, int b) {
    const double w = weight(rng);
    triplets.emplace_back(a, a, w);
    triplets.emplace_back(b, b, w);
    triplets.emplace_back(a, b, -w);
    triplets.emplace_back(b, a, -w);
  };
  for (int y = 0; y < side; ++y) {
    for (int x = 0; x < side; ++x) {
      const int i = y * side + x;
      if (x + 1 < side) add_edge(i, i + 1);
      if (y + 1 < side) add_edge(i, i + side);
      triplets.emplace_back(i, i, shift(rng));
    }
  }
  Eigen::SparseMatrix<double> A(side * side, side * side);
  A.setFromTriplets(triplets.begin(), triplets.end());
  return A;
}

Eigen::MatrixX3d random_right_hand_sides(Eigen::Index rows, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::MatrixX3d B(rows, 3);
  for (Eigen::Index i = 0; i < B.size(); ++i) B.data()[i] = normal(rng);
  return B;
}

TEST(BlockConjugateGradients, ConvergesToTheExactSolution) {
  const Eigen::SparseMatrix<double> A = random_laplacian(20, 1);
  const Eigen::MatrixX3d B = random_right_hand_sides(A.rows(), 2);
  Eigen::MatrixX3d X;
  const int iterations = block_conjugate_gradients(A, B, 1e-12, 5000, X);
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> exact(A);
  const Eigen::MatrixX3d truth = exact.solve(B);
  EXPECT_LT(iterations, 5000);
  EXPECT_LT((X - truth).cwiseAbs().maxCoeff(), 1e-6 * truth.cwiseAbs().maxCoeff());
}

// Each column takes Eigen's steps: the same solution at a loose tolerance
// (where the stopping point matters) and as many matrix products, on 8100
// rows (more than one block of rows).
TEST(BlockConjugateGradients, TakesTheStepsOfEigensSolverColumnByColumn) {
  const Eigen::SparseMatrix<double> A = random_laplacian(90, 3);
  Eigen::MatrixX3d B = random_right_hand_sides(A.rows(), 4);
  B.col(1) *= 1e3;  // the stopping rule is relative to each column
  Eigen::MatrixX3d X;
  const int iterations = block_conjugate_gradients(A, B, 1e-3, 1000, X);
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> eigen;
  eigen.setTolerance(1e-3);
  eigen.setMaxIterations(1000);
  eigen.compute(A);
  int most = 0;
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd x = eigen.solve(B.col(c));
    most = std::max(most, static_cast<int>(eigen.iterations()));
    EXPECT_LT((X.col(c) - x).norm(), 1e-9 * x.norm()) << "column " << c;
  }
  EXPECT_GT(most, 10);
  // Eigen does not count the step after which a column has converged.
  EXPECT_EQ(iterations, most + 1);
}

TEST(BlockConjugateGradients, AZeroColumnStaysZeroWhileTheOthersIterate) {
  const Eigen::SparseMatrix<double> A = random_laplacian(10, 5);
  Eigen::MatrixX3d B = random_right_hand_sides(A.rows(), 6);
  B.col(2).setZero();
  Eigen::MatrixX3d X;
  EXPECT_GT(block_conjugate_gradients(A, B, 1e-6, 1000, X), 1);
  EXPECT_TRUE(X.allFinite());
  EXPECT_EQ(X.col(2).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GT(X.col(0).norm(), 0.0);
}

// The blocks of rows sum their parts of the dot products in a fixed order:
// the same bits with one thread as with three.
TEST(BlockConjugateGradients, SameSolutionWithAnyNumberOfThreads) {
  const Eigen::SparseMatrix<double> A = random_laplacian(100, 7);
  const Eigen::MatrixX3d B = random_right_hand_sides(A.rows(), 8);
  const int threads = omp_get_max_threads();
  Eigen::MatrixX3d serial, parallel;
  omp_set_num_threads(1);
  const int serial_iterations = block_conjugate_gradients(A, B, 1e-3, 1000, serial);
  omp_set_num_threads(std::max(threads, 3));
  const int parallel_iterations = block_conjugate_gradients(A, B, 1e-3, 1000, parallel);
  omp_set_num_threads(threads);
  EXPECT_GT(serial_iterations, 10);
  EXPECT_EQ(serial_iterations, parallel_iterations);
  EXPECT_TRUE(serial == parallel);
}

}  // namespace
}  // namespace hos::texture
