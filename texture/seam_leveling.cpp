#include "texture/seam_leveling.h"

#include <Eigen/Sparse>
#include <numeric>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "texture/block_conjugate_gradients.h"

namespace hos::texture {

namespace {

double mean(const std::vector<double>& values) {
  return std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
}

// The global index of chart c's vertex i is first[c] + i.
std::vector<int> chart_vertex_offsets(const std::vector<Chart>& charts) {
  std::vector<int> first(charts.size() + 1, 0);
  for (std::size_t c = 0; c < charts.size(); ++c) {
    first[c + 1] = first[c] + static_cast<int>(charts[c].vertices.size());
  }
  return first;
}

// Colour f of every chart vertex in its chart's view, from lightly blurred
// views (a vertex sample alone is noisy), times the view's gain.
std::vector<Eigen::Vector3f> chart_vertex_colors(const TriangleMesh& mesh,
                                                 const std::vector<Chart>& charts,
                                                 const std::vector<TextureView>& views,
                                                 const std::vector<Eigen::Vector3f>& gains,
                                                 const std::vector<int>& first) {
  std::vector<Eigen::Vector3f> f(first.back());
  std::vector<std::vector<int>> charts_of_view(views.size());
  for (std::size_t c = 0; c < charts.size(); ++c) charts_of_view[charts[c].view].push_back(static_cast<int>(c));
#pragma omp parallel for schedule(dynamic)
  for (int v = 0; v < static_cast<int>(views.size()); ++v) {
    if (charts_of_view[v].empty()) continue;
    cv::Mat blurred;
    cv::GaussianBlur(views[v].image, blurred, cv::Size(5, 5), 1.0);
    for (int c : charts_of_view[v]) {
      for (std::size_t i = 0; i < charts[c].vertices.size(); ++i) {
        const Eigen::Vector3d p = views[v].project(mesh.vertices[charts[c].vertices[i]].cast<double>());
        f[first[c] + i] = gains[v].cwiseProduct(sample_rgb(blurred, p.x(), p.y()));
      }
    }
  }
  return f;
}

// The chart copies (global indices) of every mesh vertex.
std::vector<std::vector<int>> chart_copies(std::size_t num_vertices,
                                           const std::vector<Chart>& charts,
                                           const std::vector<int>& first) {
  std::vector<std::vector<int>> copies(num_vertices);
  for (std::size_t c = 0; c < charts.size(); ++c) {
    for (std::size_t i = 0; i < charts[c].vertices.size(); ++i) {
      copies[charts[c].vertices[i]].push_back(first[c] + static_cast<int>(i));
    }
  }
  return copies;
}

// Calls fn(i, j) for every pair of chart copies of one mesh vertex.
template <typename Fn>
void for_each_copy_pair(const std::vector<std::vector<int>>& copies, Fn&& fn) {
  for (const auto& list : copies) {
    for (std::size_t a = 0; a < list.size(); ++a) {
      for (std::size_t b = a + 1; b < list.size(); ++b) fn(list[a], list[b]);
    }
  }
}

// Adds w (x_i - x_j)^2 to the quadratic form.
void add_difference(std::vector<Eigen::Triplet<double>>& triplets, int i, int j, double w) {
  triplets.emplace_back(i, i, w);
  triplets.emplace_back(j, j, w);
  triplets.emplace_back(i, j, -w);
  triplets.emplace_back(j, i, -w);
}

// The matrix of the leveling energy: the seam terms, the chart edges' terms
// weighted 1 / lambda, and a tiny pull towards zero.
Eigen::SparseMatrix<double> leveling_matrix(const std::vector<std::vector<int>>& copies,
                                            const std::vector<Chart>& charts,
                                            const std::vector<int>& first,
                                            const TextureOptions& options) {
  const int n = first.back();
  std::vector<Eigen::Triplet<double>> triplets;
  for_each_copy_pair(copies, [&](int i, int j) { add_difference(triplets, i, j, 1.0); });
  const double edge_weight = 1.0 / options.leveling_regularization;
  for (std::size_t c = 0; c < charts.size(); ++c) {
    for (const auto& face : charts[c].local_faces) {
      for (int k = 0; k < 3; ++k) {
        // Interior edges appear in two faces; the double weight is harmless.
        add_difference(triplets, first[c] + face[k], first[c] + face[(k + 1) % 3], edge_weight);
      }
    }
  }
  // A tiny pull towards zero fixes the free constant of each connected part.
  for (int i = 0; i < n; ++i) triplets.emplace_back(i, i, 1e-4);
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(triplets.begin(), triplets.end());
  return A;
}

// The offsets g minimizing the leveling energy by conjugate gradients from
// zero, stopped at a relative residual of 1e-3; returns the iterations.
// (An exact solve, or one started from per-chart constants, levels further,
// and held-out photos score lower with it.)
int solve_offsets(const Eigen::SparseMatrix<double>& A,
                  const std::vector<std::vector<int>>& copies,
                  const std::vector<Eigen::Vector3f>& f,
                  std::vector<Eigen::Vector3f>& g) {
  const int n = static_cast<int>(f.size());
  // Right-hand side: -d/dg of the seam terms at g = 0.
  Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(n, 3);
  for_each_copy_pair(copies, [&](int i, int j) {
    const Eigen::RowVector3d d = (f[i] - f[j]).cast<double>().transpose();
    rhs.row(i) -= d;
    rhs.row(j) += d;
  });
  Eigen::MatrixX3d x;
  const int iterations = block_conjugate_gradients(A, rhs, 1e-3, 1000, x);
  if (!x.allFinite()) throw NumericalError("texture", "seam leveling produced non-finite offsets");
  for (int i = 0; i < n; ++i) g[i] = x.row(i).transpose().cast<float>();
  return iterations;
}

}  // namespace

SeamLeveling level_seams(const TriangleMesh& mesh,
                         const std::vector<Chart>& charts,
                         const std::vector<TextureView>& views,
                         const std::vector<Eigen::Vector3f>& gains,
                         const TextureOptions& options,
                         Reporter& reporter) {
  reporter.begin("seam leveling", 0);
  SeamLeveling result;
  const std::vector<int> first = chart_vertex_offsets(charts);
  const int n = first.back();
  const std::vector<Eigen::Vector3f> f = chart_vertex_colors(mesh, charts, views, gains, first);
  const std::vector<std::vector<int>> copies = chart_copies(mesh.vertices.size(), charts, first);
  for (const auto& list : copies) {
    if (list.size() >= 2) ++result.num_seam_vertices;
  }

  std::vector<Eigen::Vector3f> g(n, Eigen::Vector3f::Zero());
  if (options.global_leveling && result.num_seam_vertices > 0) {
    reporter.throw_if_cancelled();
    result.solver_iterations = solve_offsets(leveling_matrix(copies, charts, first, options), copies, f, g);
    reporter.debug(format_message("seam leveling: ", n, " chart vertices, ", result.solver_iterations,
                                  " conjugate-gradient steps"));
  }

  // Colour jump between chart copies, before and after leveling.
  std::vector<double> jumps_before, jumps_after;
  for_each_copy_pair(copies, [&](int i, int j) {
    jumps_before.push_back((f[i] - f[j]).norm());
    jumps_after.push_back((f[i] + g[i] - f[j] - g[j]).norm());
  });
  if (!jumps_before.empty()) {
    result.mean_seam_jump_before = mean(jumps_before);
    result.mean_seam_jump_after = mean(jumps_after);
  }
  result.seam_jumps_before = make_histogram(jumps_before, kSeamJumpPlotBins, 0.0, kSeamJumpPlotMax);
  result.seam_jumps_after = make_histogram(jumps_after, kSeamJumpPlotBins, 0.0, kSeamJumpPlotMax);
  result.offsets.resize(charts.size());
  result.vertex_colors.resize(charts.size());
  for (std::size_t c = 0; c < charts.size(); ++c) {
    result.offsets[c].assign(g.begin() + first[c], g.begin() + first[c + 1]);
    result.vertex_colors[c].resize(charts[c].vertices.size());
    for (std::size_t i = 0; i < charts[c].vertices.size(); ++i) {
      result.vertex_colors[c][i] = f[first[c] + i] + g[first[c] + i];
    }
  }
  reporter.end();
  return result;
}

}  // namespace hos::texture
