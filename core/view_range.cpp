#include "core/view_range.h"

#include <algorithm>
#include <regex>

namespace hos {

std::string ViewRange::text() const { return std::to_string(first) + "-" + std::to_string(last); }

std::vector<bool> ViewRange::selection(int num_views) const {
  std::vector<bool> selected(static_cast<std::size_t>(std::max(num_views, 0)), false);
  for (int i = std::max(first, 0); i <= last && i < num_views; ++i) selected[static_cast<std::size_t>(i)] = true;
  return selected;
}

int ViewRange::count(int num_views) const {
  const int end = std::min(last, num_views - 1);
  return std::max(0, end - std::max(first, 0) + 1);
}

std::optional<ViewRange> parse_view_range(const std::string& text) {
  const std::regex range_pattern(R"((\d{1,9})(?:-(\d{1,9}))?)");
  std::smatch m;
  if (!std::regex_match(text, m, range_pattern)) return std::nullopt;
  ViewRange range;
  range.first = std::stoi(m[1]);
  range.last = m[2].matched ? std::stoi(m[2]) : range.first;
  if (range.last < range.first) return std::nullopt;
  return range;
}

int views_per_task(int num_views, int num_tasks) {
  const int tasks = std::max(1, std::min(num_tasks, num_views));
  return std::max(1, (num_views + tasks - 1) / tasks);
}

}  // namespace hos
