// Order statistics of a sample: the value at a fraction of the sorted
// values, the median. Each takes its values by copy and partially sorts
// that copy (std::nth_element), so the cost is linear.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace hos {

// The value at index floor(fraction * (n - 1)) of the sorted values
// (fraction clamped to [0, 1]): 0 the smallest, 1 the largest. T() for no
// values.
template <typename T>
T quantile(std::vector<T> values, double fraction) {
  if (values.empty()) return T();
  const auto k = static_cast<std::size_t>(std::clamp(fraction, 0.0, 1.0) * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

// The value at index n / 2 of the sorted values: the median for an odd
// count, the upper of the two middle values for an even one. T() for no
// values.
template <typename T>
T upper_median(std::vector<T> values) {
  if (values.empty()) return T();
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace hos
