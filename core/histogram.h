// Counts of values in equal bins: the stages write them into their report
// files, the run report draws them.
#pragma once

#include <cstdint>
#include <vector>

namespace hos {

struct Histogram {
  double lo = 0.0;  // left edge of the first bin
  double hi = 1.0;  // right edge of the last bin
  std::vector<std::int64_t> counts;

  double bin_width() const { return (hi - lo) / double(counts.empty() ? 1 : counts.size()); }
  std::int64_t total() const;
};

// Bins values into `bins` equal bins over [lo, hi]; values outside are
// clamped into the end bins so that nothing is silently dropped; NaN and
// infinities are left out.
Histogram make_histogram(const std::vector<double>& values, int bins, double lo, double hi);

// One bin per integer from 0 to the largest value, at most max_value
// (larger values go into the last bin): for counts such as views per face.
Histogram make_count_histogram(const std::vector<double>& values, int max_value);

}  // namespace hos
