// Ranges of views for split runs (job arrays on a cluster, docs/scale.md):
// a stage's per-view work runs as parts over ranges of the views, numbered
// from 0 in the order of the model's image ids, then one run joins them.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace hos {

// The views first..last, inclusive. The part past the last view is empty.
struct ViewRange {
  int first = 0;
  int last = 0;

  // "FIRST-LAST", as parse_view_range reads it.
  std::string text() const;
  // Per view of num_views: whether the range holds it.
  std::vector<bool> selection(int num_views) const;
  // How many of num_views the range holds.
  int count(int num_views) const;
};

// "3-9" or "4" (= "4-4"); nothing for anything else, or when LAST < FIRST.
std::optional<ViewRange> parse_view_range(const std::string& text);

// Views per task when num_views are cut into num_tasks chunks: ceil(views / tasks),
// so task t computes t*chunk .. t*chunk + chunk - 1 (the last ones may be short or empty).
int views_per_task(int num_views, int num_tasks);

}  // namespace hos
