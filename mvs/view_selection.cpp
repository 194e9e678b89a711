#include "mvs/view_selection.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace hos::mvs {
namespace {

using PairScores = std::map<std::pair<int, int>, double>;  // (smaller id, larger id) -> score

// Sums weight(a, b, point) over the sparse points both images a < b see.
template <typename Weight>
PairScores score_image_pairs(const SparseModel& model, const Weight& weight) {
  PairScores scores;
  for (const auto& [id, point] : model.points) {
    std::set<int> seen;
    for (const auto& e : point.track) seen.insert(e.image_id);
    for (int a : seen) {
      for (int b : seen) {
        if (a < b) scores[{a, b}] += weight(a, b, point.xyz);
      }
    }
  }
  return scores;
}

double pair_score(const PairScores& scores, int a, int b) {
  const auto it = scores.find({std::min(a, b), std::max(a, b)});
  return it == scores.end() ? 0.0 : it->second;
}

}  // namespace

std::vector<std::vector<int>> select_source_views(const SparseModel& model, const MvsOptions& options) {
  const double min_angle = options.min_triangulation_angle_deg * M_PI / 180.0;
  const double good_angle = 5.0 * std::max(min_angle, 1e-3);
  const double falloff = options.source_view_angle_falloff_deg * M_PI / 180.0;
  const PairScores scores = score_image_pairs(model, [&](int a, int b, const Eigen::Vector3d& x) {
    const Eigen::Vector3d ca = model.images.at(a).center(), cb = model.images.at(b).center();
    const Eigen::Vector3d ra = (ca - x).normalized(), rb = (cb - x).normalized();
    const double angle = std::acos(std::clamp(ra.dot(rb), -1.0, 1.0));
    if (angle < min_angle) return 0.0;
    if (angle <= good_angle || falloff <= 0.0) return std::min(1.0, angle / good_angle);
    // Wider: the views see a surface at ever more different angles, so its
    // windows match worse (a ground seen at grazing angles most of all).
    const double excess = (angle - good_angle) / falloff;
    return std::exp(-0.5 * excess * excess);
  });
  std::vector<std::vector<int>> sources;
  for (const auto& [ref_id, ref] : model.images) {
    std::vector<std::pair<double, int>> candidates;
    for (const auto& [src_id, src] : model.images) {
      if (src_id == ref_id) continue;
      double score = pair_score(scores, ref_id, src_id);
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

std::vector<std::vector<int>> select_fusion_views(const SparseModel& model,
                                                  int max_views,
                                                  const std::set<int>& without_depth) {
  const auto with_depth = static_cast<int>(std::count_if(
      model.images.begin(), model.images.end(), [&](const auto& e) { return !without_depth.contains(e.first); }));
  // Limited: every list, a skipped view's too, has more than max_views candidates.
  const bool limited = max_views > 0 && with_depth - 1 > max_views;
  const PairScores shared =
      limited ? score_image_pairs(model, [](int, int, const Eigen::Vector3d&) { return 1.0; }) : PairScores{};
  std::vector<std::vector<int>> views;
  for (const auto& [ref_id, ref] : model.images) {
    std::vector<std::pair<double, int>> candidates;
    for (const auto& [id, image] : model.images) {
      if (id != ref_id && !without_depth.contains(id)) candidates.emplace_back(pair_score(shared, ref_id, id), id);
    }
    // Most shared points first, then the lower id.
    std::stable_sort(candidates.begin(), candidates.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    if (limited) candidates.resize(static_cast<std::size_t>(max_views));
    std::vector<int> chosen(candidates.size());
    std::transform(candidates.begin(), candidates.end(), chosen.begin(), [](const auto& c) { return c.second; });
    views.push_back(std::move(chosen));
  }
  return views;
}

}  // namespace hos::mvs
