// Discrete curvature of a triangle mesh and the figures of the paper's
// Table 1 (Pan & Skala): triangles, RMS distance of the input points to the
// surface, average and maximum absolute mean and Gaussian curvature.
//
// Operators (Meyer, Desbrun, Schroeder, Barr 2003, "Discrete
// differential-geometry operators for triangulated 2-manifolds"):
//  - mean curvature H from the cotangent Laplacian,
//      H_i n_i = 1/(4 A_i) * sum_j (cot a_ij + cot b_ij)(x_i - x_j)   (Eq. 8),
//    signed positive where the surface bends away from its outward normal
//    (a sphere with counter-clockwise faces has H = +1/r);
//  - Gaussian curvature from the angle defect,
//      K_i = (2 pi - sum_f theta_f,i) / A_i                             (Eq. 9);
//  - A_i is the mixed Voronoi area (Sec. 3.3, Fig. 4): the Voronoi area for
//    non-obtuse triangles, half or a quarter of the triangle's area otherwise.
// Boundary vertices (on an edge with a single face) get no curvature: both
// operators are defined for interior vertices only.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/reporter.h"
#include "core/types.h"

namespace hos::eval {

struct VertexCurvature {
  std::vector<double> mean;        // H per vertex (NaN where not defined)
  std::vector<double> gaussian;    // K per vertex (NaN where not defined)
  std::vector<double> mixed_area;  // A_i
  std::vector<bool> defined;       // interior vertex with A_i > 0
};

VertexCurvature compute_vertex_curvature(const TriangleMesh& mesh);

struct CurvatureStats {
  std::size_t triangles = 0;
  std::size_t vertices_measured = 0;         // interior vertices with positive area
  std::optional<double> rms_point_distance;  // input points -> surface, if points were given
  double mean_abs_h = 0.0, max_abs_h = 0.0;  // unweighted mean over measured vertices
  double mean_abs_k = 0.0, max_abs_k = 0.0;
  // 99th percentiles: the rough parts of a surface without its single worst
  // vertices (a marching-cubes sliver can set the maximum on its own).
  double p99_abs_h = 0.0, p99_abs_k = 0.0;
};

// points may be null (no RMS figure then).
CurvatureStats compute_curvature_stats(const TriangleMesh& mesh,
                                       const std::vector<Eigen::Vector3f>* points,
                                       Reporter& reporter);

}  // namespace hos::eval
