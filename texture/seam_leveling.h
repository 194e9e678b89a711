// Global seam leveling (Waechter, Moehrle, Goesele 2014, Sec. 5.1): an
// additive colour offset g per chart vertex, linear inside each face,
// minimizing
//   sum over seam vertices v, chart copies i != j of v: (f_i + g_i - f_j - g_j)^2
//   + 1/lambda * sum over chart edges (a, b): (g_a - g_b)^2   (+ a tiny g^2)
// where f_i is the (exposure-corrected) colour of v in chart i's view.
// Sparse least squares, solved by diagonally preconditioned conjugate
// gradients, the three channels side by side.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/histogram.h"
#include "core/reporter.h"
#include "core/types.h"
#include "texture/charts.h"
#include "texture/texture_options.h"
#include "texture/texture_view.h"

namespace hos::texture {

struct SeamLeveling {
  // Per chart, per chart vertex: RGB offset (8-bit scale) and the leveled
  // colour f + g of the vertex.
  std::vector<std::vector<Eigen::Vector3f>> offsets;
  std::vector<std::vector<Eigen::Vector3f>> vertex_colors;
  int num_seam_vertices = 0;
  // Mean colour difference between chart copies of seam vertices.
  double mean_seam_jump_before = 0.0;
  double mean_seam_jump_after = 0.0;
  // The same per pair of chart copies, binned over [0, kSeamJumpPlotMax]
  // (larger jumps in the last bin), for the run report.
  Histogram seam_jumps_before, seam_jumps_after;
  int solver_iterations = 0;
};

inline constexpr double kSeamJumpPlotMax = 64.0;  // 8-bit RGB distance
inline constexpr int kSeamJumpPlotBins = 64;

// gains: per-view RGB exposure gains applied to the views' colours. With
// options.global_leveling false, offsets are zero (the colours are still
// returned).
SeamLeveling level_seams(const TriangleMesh& mesh,
                         const std::vector<Chart>& charts,
                         const std::vector<TextureView>& views,
                         const std::vector<Eigen::Vector3f>& gains,
                         const TextureOptions& options,
                         Reporter& reporter);

}  // namespace hos::texture
