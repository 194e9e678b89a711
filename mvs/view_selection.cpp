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

// A candidate source of one reference view: the reference's sparse points
// it sees too (indices into the reference's points) with their weights.
struct SharedPoints {
  int id = 0;
  std::vector<std::pair<std::size_t, double>> points;
};

// The sparse points with the images that see each (once each), and per
// image the indices of the points it sees.
struct Visibility {
  std::vector<std::pair<Eigen::Vector3d, std::vector<int>>> points;
  std::map<int, std::vector<std::size_t>> of_image;
};

Visibility visibility(const SparseModel& model) {
  Visibility v;
  for (const auto& [id, point] : model.points) {
    std::vector<int> images;
    for (const auto& e : point.track) images.push_back(e.image_id);
    std::sort(images.begin(), images.end());
    images.erase(std::unique(images.begin(), images.end()), images.end());
    for (int image : images) v.of_image[image].push_back(v.points.size());
    v.points.emplace_back(point.xyz, std::move(images));
  }
  return v;
}

// The candidates of reference ref_id: the views seeing one of its points,
// each with the points (indices into the reference's) and their weights.
template <typename Weight>
std::vector<SharedPoints> shared_points(const Visibility& visibility, int ref_id, const Weight& weight) {
  std::map<int, SharedPoints> by_id;
  const auto it = visibility.of_image.find(ref_id);
  if (it == visibility.of_image.end()) return {};
  for (std::size_t k = 0; k < it->second.size(); ++k) {
    const auto& [xyz, images] = visibility.points[it->second[k]];
    for (int s : images) {
      if (s == ref_id) continue;
      SharedPoints& c = by_id[s];
      c.id = s;
      c.points.emplace_back(k, weight(std::min(ref_id, s), std::max(ref_id, s), xyz));
    }
  }
  std::vector<SharedPoints> candidates;
  candidates.reserve(by_id.size());
  for (auto& [id, c] : by_id) candidates.push_back(std::move(c));
  return candidates;
}

// Up to options.num_source_views of the candidates, one at a time: each
// time the one whose shared points weigh most, a point counting
// source_view_covered_weight once best_k of the sources chosen before see
// it, so a view that sees what the chosen ones do not (the ground along the
// frame's edges, say) wins over one more view of what they already cover.
// At a weight of 1 this ranks by the weighted count of shared points.
std::vector<int> choose_covering_sources(std::vector<SharedPoints> candidates,
                                         std::size_t reference_points,
                                         const MvsOptions& options) {
  std::vector<int> seen_by(reference_points, 0);
  std::vector<int> chosen;
  while (static_cast<int>(chosen.size()) < options.num_source_views && !candidates.empty()) {
    std::size_t best = 0;
    double best_score = -1.0;
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      double score = 0.0;
      for (const auto& [p, w] : candidates[k].points) {
        score += seen_by[p] >= options.best_k ? w * options.source_view_covered_weight : w;
      }
      // Equal scores: the higher id, as a ranking in descending order.
      if (score > best_score || (score == best_score && candidates[k].id > candidates[best].id)) {
        best = k;
        best_score = score;
      }
    }
    if (!(best_score > 0.0)) break;
    chosen.push_back(candidates[best].id);
    for (const auto& point : candidates[best].points) ++seen_by[point.first];
    candidates.erase(candidates.begin() + static_cast<std::ptrdiff_t>(best));
  }
  return chosen;
}

}  // namespace

std::vector<std::vector<int>> select_source_views(const SparseModel& model, const MvsOptions& options) {
  const double min_angle = options.min_triangulation_angle_deg * M_PI / 180.0;
  const double good_angle = 5.0 * std::max(min_angle, 1e-3);
  const double falloff = options.source_view_angle_falloff_deg * M_PI / 180.0;
  const auto weight = [&](int a, int b, const Eigen::Vector3d& x) {
    const Eigen::Vector3d ca = model.images.at(a).center(), cb = model.images.at(b).center();
    const Eigen::Vector3d ra = (ca - x).normalized(), rb = (cb - x).normalized();
    const double angle = std::acos(std::clamp(ra.dot(rb), -1.0, 1.0));
    if (angle < min_angle) return 0.0;
    if (angle <= good_angle || falloff <= 0.0) return std::min(1.0, angle / good_angle);
    // Wider: the views see a surface at ever more different angles, so its
    // windows match worse (a ground seen at grazing angles most of all).
    const double excess = (angle - good_angle) / falloff;
    return std::exp(-0.5 * excess * excess);
  };
  const Visibility seen = visibility(model);
  std::vector<std::vector<int>> sources;
  for (const auto& [ref_id, ref] : model.images) {
    if (!model.points.empty()) {
      const auto it = seen.of_image.find(ref_id);
      const std::size_t count = it == seen.of_image.end() ? 0 : it->second.size();
      sources.push_back(choose_covering_sources(shared_points(seen, ref_id, weight), count, options));
      continue;
    }
    // No sparse points: views looking the same way from a useful baseline.
    std::vector<std::pair<double, int>> candidates;
    for (const auto& [src_id, src] : model.images) {
      if (src_id == ref_id) continue;
      const double cos_view = ref.viewing_direction().dot(src.viewing_direction());
      const double angle = std::acos(std::clamp(cos_view, -1.0, 1.0));
      if (angle >= min_angle && angle < M_PI / 3.0) candidates.emplace_back(1.0 - angle / (M_PI / 3.0), src_id);
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
