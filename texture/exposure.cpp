#include "texture/exposure.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>

namespace hos::texture {

namespace {

struct LogRatioResidual {
  double log_ratio;  // log(C_fu) - log(C_fv) of one channel
  template <typename T>
  bool operator()(const T* const a_u, const T* const a_v, T* residual) const {
    residual[0] = T(log_ratio) + a_u[0] - a_v[0];
    return true;
  }
};

struct PriorResidual {
  double weight;
  template <typename T>
  bool operator()(const T* const a, T* residual) const {
    residual[0] = T(weight) * a[0];
    return true;
  }
};

// Log-gains of one colour channel (k = 0, 1, 2).
std::vector<double> channel_log_gains(const FaceViewCandidates& candidates,
                                      int num_views,
                                      int k,
                                      std::vector<int>& pairs_per_view) {
  std::vector<double> log_gain(num_views, 0.0);
  ceres::Problem problem;
  // Subsample faces so the problem stays small (about 100k view pairs): the
  // gains are a handful of unknowns, more pairs only cost time and memory.
  const int num_faces = candidates.num_faces();
  const int stride = std::max<int>(1, static_cast<int>(candidates.samples.size() / 100000));
  for (int f = 0; f < num_faces; f += stride) {
    const int b = candidates.begin(f), e = candidates.end(f);
    // Each view against the next one of the face: a chain per face.
    for (int i = b; i + 1 < e; ++i) {
      const FaceViewSample& s = candidates.samples[i];
      const FaceViewSample& t = candidates.samples[i + 1];
      const float cu = s.mean_rgb[k], cv = t.mean_rgb[k];
      // Dark or saturated faces say little about the gain.
      if (cu < 8.0f || cv < 8.0f || cu > 250.0f || cv > 250.0f) continue;
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<LogRatioResidual, 1, 1, 1>(new LogRatioResidual{std::log(cu) - std::log(cv)}),
          new ceres::CauchyLoss(0.05), &log_gain[s.view], &log_gain[t.view]);
      ++pairs_per_view[s.view];
      ++pairs_per_view[t.view];
    }
  }
  // A weak prior pins the free overall scale (and views without overlap).
  for (int v = 0; v < num_views; ++v) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PriorResidual, 1, 1>(new PriorResidual{1e-2}), nullptr,
                             &log_gain[v]);
  }
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = 50;
  solver_options.num_threads = 2;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  double mean = 0.0;
  int counted = 0;
  for (int v = 0; v < num_views; ++v) {
    if (pairs_per_view[v] > 0) {
      mean += log_gain[v];
      ++counted;
    }
  }
  if (counted > 0) mean /= counted;
  for (int v = 0; v < num_views; ++v) log_gain[v] = pairs_per_view[v] > 0 ? log_gain[v] - mean : 0.0;
  return log_gain;
}

}  // namespace

std::vector<Eigen::Vector3f> estimate_exposure_gains(const FaceViewCandidates& candidates,
                                                     int num_views,
                                                     Reporter& reporter) {
  std::vector<Eigen::Vector3f> gains(num_views, Eigen::Vector3f::Ones());
  if (num_views < 2) return gains;
  reporter.begin("exposure gains", 3);
  for (int k = 0; k < 3; ++k) {
    reporter.throw_if_cancelled();
    std::vector<int> pairs(num_views, 0);
    const std::vector<double> log_gain = channel_log_gains(candidates, num_views, k, pairs);
    for (int v = 0; v < num_views; ++v) gains[v][k] = static_cast<float>(std::exp(log_gain[v]));
    reporter.advance();
  }
  reporter.end();
  return gains;
}

void apply_exposure_gains(const std::vector<Eigen::Vector3f>& gains, FaceViewCandidates& candidates) {
  for (auto& s : candidates.samples) s.mean_rgb = s.mean_rgb.cwiseProduct(gains[s.view]);
}

}  // namespace hos::texture
