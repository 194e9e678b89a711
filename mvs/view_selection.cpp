#include "mvs/view_selection.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace hos::mvs {

std::vector<std::vector<int>> select_source_views(const SparseModel& model, const MvsOptions& options) {
  const double min_angle = options.min_triangulation_angle_deg * M_PI / 180.0;
  std::map<std::pair<int, int>, double> scores;
  for (const auto& [id, point] : model.points) {
    std::set<int> seen;
    for (const auto& e : point.track) seen.insert(e.image_id);
    for (int a : seen) {
      for (int b : seen) {
        if (a >= b) continue;
        const Eigen::Vector3d ca = model.images.at(a).center(), cb = model.images.at(b).center();
        const Eigen::Vector3d ra = (ca - point.xyz).normalized(), rb = (cb - point.xyz).normalized();
        const double angle = std::acos(std::clamp(ra.dot(rb), -1.0, 1.0));
        if (angle < min_angle) continue;
        const double weight = std::min(1.0, angle / (5.0 * std::max(min_angle, 1e-3)));
        scores[{a, b}] += weight;
      }
    }
  }
  std::vector<std::vector<int>> sources;
  for (const auto& [ref_id, ref] : model.images) {
    std::vector<std::pair<double, int>> candidates;
    for (const auto& [src_id, src] : model.images) {
      if (src_id == ref_id) continue;
      const auto it = scores.find({std::min(ref_id, src_id), std::max(ref_id, src_id)});
      double score = it == scores.end() ? 0.0 : it->second;
      if (model.points.empty()) {
        // No sparse points: views looking the same way from a useful baseline.
        const double cos_view = ref.viewing_direction().dot(src.viewing_direction());
        const double angle = std::acos(std::clamp(cos_view, -1.0, 1.0));
        if (angle >= min_angle && angle < M_PI / 3.0) score = 1.0 - angle / (M_PI / 3.0);
      }
      if (score > 0.0) candidates.emplace_back(score, src_id);
    }
    std::sort(candidates.begin(), candidates.end(), std::greater<>());
    std::vector<int> chosen;
    for (const auto& [score, id] : candidates) {
      if (static_cast<int>(chosen.size()) >= options.num_source_views) break;
      chosen.push_back(id);
    }
    sources.push_back(std::move(chosen));
  }
  return sources;
}

}  // namespace hos::mvs
