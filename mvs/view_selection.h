// Choosing the source views of each reference view from the sparse model.
#pragma once

#include <set>
#include <vector>

#include "core/sparse_model.h"
#include "mvs/mvs_options.h"

namespace hos::mvs {

// For each image id of the model (in map order), up to num_source_views
// other image ids, in the order chosen. A source scores by the sparse points
// both views see, each weighted by how well its triangulation angle suits
// stereo (zero below the minimum angle, rising to 1 at 5x it, then falling
// off as a Gaussian of width source_view_angle_falloff_deg). Sources are
// chosen one at a time, the best-scoring first; a point that best_k chosen
// sources already see counts source_view_covered_weight toward the next, so
// the reference's frame is covered by best_k sources where views see it.
// Without shared points, by the angle between the viewing directions and the
// baseline. Views that share nothing usable get no sources.
std::vector<std::vector<int>> select_source_views(const SparseModel& model, const MvsOptions& options);

// For each image id of the model (in map order), the other image ids fusion
// checks its depths against: every other image with a depth map (not in
// without_depth) when there are at most max_views of them (or max_views is
// 0), otherwise the max_views of them that share the most sparse points
// with it (most first).
std::vector<std::vector<int>> select_fusion_views(const SparseModel& model,
                                                  int max_views,
                                                  const std::set<int>& without_depth = {});

}  // namespace hos::mvs
