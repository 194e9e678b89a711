#include "texture/seam_leveling.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <opencv2/imgproc.hpp>

#include "core/error.h"

namespace hos::texture {

SeamLeveling level_seams(const TriangleMesh& mesh, const std::vector<Chart>& charts,
                         const std::vector<TextureView>& views, const std::vector<Eigen::Vector3f>& gains,
                         const TextureOptions& options, Reporter& reporter) {
  reporter.begin("seam leveling", 0);
  SeamLeveling result;
  const int num_charts = static_cast<int>(charts.size());
  // Global index of every chart vertex.
  std::vector<int> first(num_charts + 1, 0);
  for (int c = 0; c < num_charts; ++c) {
    first[c + 1] = first[c] + static_cast<int>(charts[c].vertices.size());
  }
  const int n = first.back();

  // Vertex colours from lightly blurred views (a vertex sample alone is noisy).
  std::vector<Eigen::Vector3f> f(n);
  {
    std::vector<std::vector<int>> charts_of_view(views.size());
    for (int c = 0; c < num_charts; ++c) charts_of_view[charts[c].view].push_back(c);
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
  }

  // Chart copies of every mesh vertex.
  std::vector<std::vector<int>> copies(mesh.vertices.size());
  for (int c = 0; c < num_charts; ++c) {
    for (std::size_t i = 0; i < charts[c].vertices.size(); ++i) {
      copies[charts[c].vertices[i]].push_back(first[c] + static_cast<int>(i));
    }
  }

  std::vector<Eigen::Triplet<double>> triplets;
  double jump_before = 0.0;
  int num_pairs = 0;
  for (const auto& list : copies) {
    if (list.size() < 2) continue;
    ++result.num_seam_vertices;
    for (std::size_t a = 0; a < list.size(); ++a) {
      for (std::size_t b = a + 1; b < list.size(); ++b) {
        const int i = list[a], j = list[b];
        triplets.emplace_back(i, i, 1.0);
        triplets.emplace_back(j, j, 1.0);
        triplets.emplace_back(i, j, -1.0);
        triplets.emplace_back(j, i, -1.0);
        jump_before += (f[i] - f[j]).norm();
        ++num_pairs;
      }
    }
  }
  const double edge_weight = 1.0 / options.leveling_regularization;
  for (int c = 0; c < num_charts; ++c) {
    for (const auto& face : charts[c].local_faces) {
      for (int k = 0; k < 3; ++k) {
        const int i = first[c] + face[k], j = first[c] + face[(k + 1) % 3];
        // Interior edges appear in two faces; the double weight is harmless.
        triplets.emplace_back(i, i, edge_weight);
        triplets.emplace_back(j, j, edge_weight);
        triplets.emplace_back(i, j, -edge_weight);
        triplets.emplace_back(j, i, -edge_weight);
      }
    }
  }
  // A tiny pull towards zero fixes the free constant of each connected part.
  for (int i = 0; i < n; ++i) triplets.emplace_back(i, i, 1e-4);

  std::vector<Eigen::Vector3f> g(n, Eigen::Vector3f::Zero());
  if (options.global_leveling && result.num_seam_vertices > 0) {
    Eigen::SparseMatrix<double> A(n, n);
    A.setFromTriplets(triplets.begin(), triplets.end());
    // Lower only: Eigen parallelizes the Lower|Upper product with OpenMP, whose
    // per-iteration synchronization costs more than it gains on a busy machine.
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower> solver;
    solver.setMaxIterations(1000);
    solver.setTolerance(1e-3);
    solver.compute(A);
    for (int channel = 0; channel < 3; ++channel) {
      reporter.throw_if_cancelled();
      // Right-hand side: -d/dg of the seam terms at g = 0.
      Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
      for (const auto& list : copies) {
        for (std::size_t a = 0; a < list.size(); ++a) {
          for (std::size_t b = a + 1; b < list.size(); ++b) {
            const double d = f[list[a]][channel] - f[list[b]][channel];
            rhs[list[a]] -= d;
            rhs[list[b]] += d;
          }
        }
      }
      const Eigen::VectorXd x = solver.solve(rhs);
      if (!x.allFinite()) throw NumericalError("texture", "seam leveling produced non-finite offsets");
      result.solver_iterations = std::max(result.solver_iterations, static_cast<int>(solver.iterations()));
      for (int i = 0; i < n; ++i) g[i][channel] = static_cast<float>(x[i]);
    }
  }

  double jump_after = 0.0;
  for (const auto& list : copies) {
    for (std::size_t a = 0; a < list.size(); ++a) {
      for (std::size_t b = a + 1; b < list.size(); ++b) {
        jump_after += (f[list[a]] + g[list[a]] - f[list[b]] - g[list[b]]).norm();
      }
    }
  }
  if (num_pairs > 0) {
    result.mean_seam_jump_before = jump_before / num_pairs;
    result.mean_seam_jump_after = jump_after / num_pairs;
  }
  result.offsets.resize(num_charts);
  result.vertex_colors.resize(num_charts);
  for (int c = 0; c < num_charts; ++c) {
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
