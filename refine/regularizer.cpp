#include "refine/regularizer.h"

#include <Eigen/Geometry>
#include <Eigen/IterativeLinearSolvers>
#include <cmath>

#include "core/error.h"

namespace hos::refine {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// The regulariser's matrix M, so that R(x) = sum over x, y, z of c^T M c.
// Thin plate: L^T L with L = I - D^-1 A (umbrella). Membrane: (D - A) / 6,
// which matches L on a regular mesh (valence 6).
SparseMatrix regularizer_matrix(const VertexRings& rings, Regularizer regularizer) {
  const int n = static_cast<int>(rings.offsets.size()) - 1;
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(rings.neighbors.size() + n);
  const bool thin_plate = regularizer == Regularizer::kThinPlate;
  for (int v = 0; v < n; ++v) {
    const int degree = rings.degree(v);
    if (degree == 0) continue;
    entries.emplace_back(v, v, thin_plate ? 1.0 : degree / 6.0);
    for (int k = rings.offsets[v]; k < rings.offsets[v + 1]; ++k) {
      entries.emplace_back(v, rings.neighbors[k], thin_plate ? -1.0 / degree : -1.0 / 6.0);
    }
  }
  SparseMatrix m(n, n);
  m.setFromTriplets(entries.begin(), entries.end());
  if (!thin_plate) return m;
  return SparseMatrix(m.transpose() * m);
}

// m with an explicit (possibly zero) entry at every diagonal position, and
// where those entries are in its values.
SparseMatrix with_full_diagonal(const SparseMatrix& m, std::vector<int>& diagonal) {
  const int n = static_cast<int>(m.rows());
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(m.nonZeros() + n);
  for (int i = 0; i < n; ++i) {
    entries.emplace_back(i, i, 0.0);
    for (SparseMatrix::InnerIterator it(m, i); it; ++it)
      entries.emplace_back(i, static_cast<int>(it.col()), it.value());
  }
  SparseMatrix full(n, n);
  full.setFromTriplets(entries.begin(), entries.end());
  full.makeCompressed();
  diagonal.assign(n, -1);
  for (int i = 0; i < n; ++i) {
    for (int k = full.outerIndexPtr()[i]; k < full.outerIndexPtr()[i + 1]; ++k) {
      if (full.innerIndexPtr()[k] == i) diagonal[i] = k;
    }
  }
  return full;
}

Eigen::MatrixX3d positions(const TriangleMesh& mesh) {
  Eigen::MatrixX3d x(mesh.vertices.size(), 3);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) x.row(v) = mesh.vertices[v].cast<double>().transpose();
  return x;
}

}  // namespace

DisplacementSolver::DisplacementSolver(const VertexRings& rings, const RefineOptions& options)
    : lambda_(options.lambda), anchor_weight_(options.anchor_weight) {
  regularizer_ = with_full_diagonal(regularizer_matrix(rings, options.regularizer), diagonal_);
  system_ = regularizer_;
}

std::vector<float> DisplacementSolver::solve(const TriangleMesh& mesh,
                                             const std::vector<Eigen::Vector3f>& normals,
                                             const std::vector<VertexTarget>& targets,
                                             double max_offset,
                                             SolveStats* stats) {
  const int n = static_cast<int>(mesh.vertices.size());
  if (n != regularizer_.rows()) throw NumericalError("refine", "the displacement solve got another mesh");
  // Step 1: the quadratic in s. With x' = x + diag(n) s per coordinate,
  // R(x') has Hessian M_ij (n_i . n_j) and gradient n_i . (M X)_i at s = 0;
  // the system has M's pattern, so its values are filled in place.
  const Eigen::MatrixX3d mx = regularizer_ * positions(mesh);
  SparseMatrix& a = system_;
  const int* outer = a.outerIndexPtr();
  const int* inner = a.innerIndexPtr();
  const double* m = regularizer_.valuePtr();
  double* values = a.valuePtr();
  Eigen::VectorXd b(n);
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d ni = normals[i].cast<double>();
    for (int k = outer[i]; k < outer[i + 1]; ++k) values[k] = m[k] * lambda_ * ni.dot(normals[inner[k]].cast<double>());
    const double w = targets[i].weight;
    values[diagonal_[i]] += w + anchor_weight_;
    b[i] = w * targets[i].offset - lambda_ * ni.dot(mx.row(i).transpose());
  }
  // Step 2: conjugate gradients from s = 0 (Jacobi: the anchor and target
  // weights dominate the diagonal's spread).
  Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper> cg;
  cg.setTolerance(1e-6);
  cg.setMaxIterations(1000);
  cg.compute(a);
  const Eigen::VectorXd s = cg.solve(b);
  if (!s.allFinite()) throw NumericalError("refine", "the displacement solve gave non-finite values");
  if (stats) {
    stats->iterations = static_cast<int>(cg.iterations());
    stats->relative_residual = cg.error();
  }
  // Step 3: no vertex moves farther than the search reached.
  std::vector<float> out(n);
  for (int i = 0; i < n; ++i) out[i] = static_cast<float>(std::clamp(s[i], -max_offset, max_offset));
  return out;
}

std::vector<float> solve_displacements(const TriangleMesh& mesh,
                                       const VertexRings& rings,
                                       const std::vector<Eigen::Vector3f>& normals,
                                       const std::vector<VertexTarget>& targets,
                                       double max_offset,
                                       const RefineOptions& options,
                                       SolveStats* stats) {
  return DisplacementSolver(rings, options).solve(mesh, normals, targets, max_offset, stats);
}

double regularizer_energy(const TriangleMesh& mesh, const VertexRings& rings, Regularizer regularizer) {
  const Eigen::MatrixX3d x = positions(mesh);
  return (x.transpose() * (regularizer_matrix(rings, regularizer) * x)).trace();
}

}  // namespace hos::refine
