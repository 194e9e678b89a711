#include "core/histogram.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hos {

std::int64_t Histogram::total() const { return std::accumulate(counts.begin(), counts.end(), std::int64_t{0}); }

Histogram make_histogram(const std::vector<double>& values, int bins, double lo, double hi) {
  Histogram h;
  h.lo = lo;
  h.hi = hi > lo ? hi : lo + 1.0;
  h.counts.assign(static_cast<std::size_t>(std::max(bins, 1)), 0);
  const double width = h.bin_width();
  const auto last = static_cast<std::int64_t>(h.counts.size()) - 1;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    const auto bin = static_cast<std::int64_t>(std::floor((v - h.lo) / width));
    h.counts[static_cast<std::size_t>(std::clamp<std::int64_t>(bin, 0, last))]++;
  }
  return h;
}

Histogram make_count_histogram(const std::vector<double>& values, int max_value) {
  double top = 1.0;
  for (double v : values) {
    if (std::isfinite(v)) top = std::max(top, v);
  }
  const int last = std::clamp(static_cast<int>(std::ceil(top)), 1, std::max(max_value, 1));
  // Bin k is centred on the integer k.
  return make_histogram(values, last + 1, -0.5, double(last) + 0.5);
}

}  // namespace hos
