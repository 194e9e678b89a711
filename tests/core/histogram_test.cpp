#include "core/histogram.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hos {
namespace {

TEST(Histogram, OutliersGoToTheEndBinsAndNonFiniteValuesAreLeftOut) {
  const Histogram h = make_histogram({-1.0, 0.1, 0.9, 5.0, std::nan(""), INFINITY}, 2, 0.0, 1.0);
  ASSERT_EQ(h.counts.size(), 2u);
  EXPECT_EQ(h.counts[0], 2);
  EXPECT_EQ(h.counts[1], 2);
  EXPECT_EQ(h.total(), 4);
  EXPECT_DOUBLE_EQ(h.bin_width(), 0.5);
}

TEST(Histogram, CountHistogramHasOneBinPerIntegerUpToTheCap) {
  const Histogram h = make_count_histogram({0, 1, 1, 3}, 10);
  ASSERT_EQ(h.counts.size(), 4u);  // 0, 1, 2, 3
  EXPECT_EQ(h.counts, (std::vector<std::int64_t>{1, 2, 0, 1}));
  const Histogram capped = make_count_histogram({2, 50}, 5);
  ASSERT_EQ(capped.counts.size(), 6u);  // 0..5, 50 in the last bin
  EXPECT_EQ(capped.counts[2], 1);
  EXPECT_EQ(capped.counts[5], 1);
}

}  // namespace
}  // namespace hos
