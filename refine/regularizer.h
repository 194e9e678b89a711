// The refinement's linear step: normal displacements s of the vertices that
// balance the photometric targets against a smoothness energy of the moved
// surface x + s n,
//
//   E(s) = sum_v w_v (s_v - d_v)^2 + a s_v^2 + lambda R(x + s n),
//
// with R the thin-plate energy |L x|^2 (L the umbrella Laplacian, a discrete
// bi-Laplacian: the analogue of Pan & Skala's eq. (3) on the surface, which
// costs nothing for planes and little for smooth curved parts, so it neither
// shrinks nor wrinkles where the photos say nothing) or the membrane energy
// x^T K x (eq. (1)'s analogue, the area term; it pulls curved parts inwards).
// The anchor a keeps the system positive definite where no vertex has a target.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "core/types.h"
#include "refine/mesh_geometry.h"
#include "refine/photo_consistency.h"
#include "refine/refine_options.h"

namespace hos::refine {

struct SolveStats {
  int iterations = 0;
  double relative_residual = 0.0;
};

// The solve for one mesh connectivity: the regulariser's matrix is built
// once (a level's rounds share it) and each round only fills the system's
// values in its pattern.
class DisplacementSolver {
 public:
  DisplacementSolver(const VertexRings& rings, const RefineOptions& options);

  // Minimises E(s) (conjugate gradients, Jacobi preconditioner); each s_v is
  // then clamped to [-max_offset, max_offset]. Throws NumericalError when the
  // solution is not finite.
  std::vector<float> solve(const TriangleMesh& mesh,
                           const std::vector<Eigen::Vector3f>& normals,
                           const std::vector<VertexTarget>& targets,
                           double max_offset,
                           SolveStats* stats = nullptr);

 private:
  using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  double lambda_ = 0.0, anchor_weight_ = 0.0;
  SparseMatrix regularizer_;   // with an entry on every diagonal position
  std::vector<int> diagonal_;  // index of (v, v) in regularizer_'s values
  SparseMatrix system_;        // regularizer_'s pattern, each solve's values
};

// One solve (DisplacementSolver for a single round).
std::vector<float> solve_displacements(const TriangleMesh& mesh,
                                       const VertexRings& rings,
                                       const std::vector<Eigen::Vector3f>& normals,
                                       const std::vector<VertexTarget>& targets,
                                       double max_offset,
                                       const RefineOptions& options,
                                       SolveStats* stats = nullptr);

// R(x) for the mesh as it is (the regulariser's share of the energy, per vertex).
double regularizer_energy(const TriangleMesh& mesh, const VertexRings& rings, Regularizer regularizer);

}  // namespace hos::refine
