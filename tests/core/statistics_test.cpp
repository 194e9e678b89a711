#include "core/statistics.h"

#include <gtest/gtest.h>

namespace hos {
namespace {

TEST(Statistics, QuantileIsTheValueAtTheFractionOfTheSortedValues) {
  const std::vector<double> values{5, 1, 4, 2, 3};  // sorted: 1 2 3 4 5
  EXPECT_EQ(quantile(values, 0.0), 1.0);
  EXPECT_EQ(quantile(values, 1.0), 5.0);
  EXPECT_EQ(quantile(values, 0.5), 3.0);
  EXPECT_EQ(quantile(values, 0.99), 4.0) << "index floor(0.99 * 4) = 3";
  EXPECT_EQ(quantile(values, -1.0), 1.0) << "fractions are clamped";
  EXPECT_EQ(quantile(values, 7.0), 5.0);
  EXPECT_EQ(quantile(std::vector<float>{}, 0.5), 0.0f);
}

TEST(Statistics, UpperMedianTakesTheUpperMiddleOfAnEvenCount) {
  EXPECT_EQ(upper_median(std::vector<double>{3, 1, 2}), 2.0);
  EXPECT_EQ(upper_median(std::vector<double>{4, 1, 3, 2}), 3.0);
  EXPECT_EQ(upper_median(std::vector<double>{}), 0.0);
}

}  // namespace
}  // namespace hos
