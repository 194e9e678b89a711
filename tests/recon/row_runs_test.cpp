// recon/row_runs.*: node sets as runs per row against a brute-force mask of
// one byte per node.
#include "recon/row_runs.h"

#include <gtest/gtest.h>

#include <random>

namespace hos::recon {
namespace {

using Mask = std::vector<std::uint8_t>;

GridGeometry small_grid() {
  GridGeometry g;
  g.dims = Eigen::Vector3i(23, 17, 13);
  g.spacing = 0.1;
  return g;
}

// Runs from a mask, row after row.
RowRuns runs_of(const GridGeometry& g, const Mask& mask) {
  RowRuns set;
  set.dims = g.dims;
  set.row_begin.push_back(0);
  for (int k = 0; k < g.dims.z(); ++k) {
    for (int j = 0; j < g.dims.y(); ++j) {
      for (int i = 0; i < g.dims.x();) {
        if (!mask[g.index(i, j, k)]) {
          ++i;
          continue;
        }
        const int begin = i;
        while (i < g.dims.x() && mask[g.index(i, j, k)]) ++i;
        set.runs.push_back({begin, i});
      }
      set.row_begin.push_back(static_cast<std::int64_t>(set.runs.size()));
    }
  }
  return set;
}

Mask random_mask(const GridGeometry& g, double fill, unsigned seed) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution on(fill);
  Mask m(g.num_nodes());
  for (auto& v : m) v = on(rng);
  return m;
}

void expect_equal(const RowRuns& got, const Mask& want, const GridGeometry& g, const char* what) {
  std::int64_t count = 0;
  for (int k = 0; k < g.dims.z(); ++k) {
    for (int j = 0; j < g.dims.y(); ++j) {
      for (int i = 0; i < g.dims.x(); ++i) {
        ASSERT_EQ(got.contains(i, j, k), want[g.index(i, j, k)] != 0) << what << " at " << i << " " << j << " " << k;
        count += want[g.index(i, j, k)];
      }
    }
  }
  EXPECT_EQ(got.count(), count) << what;
  // Runs are ascending and apart, so the count is the node count.
  for (std::int64_t row = 0; row < got.rows(); ++row) {
    for (std::int64_t r = got.row_begin[row] + 1; r < got.row_begin[row + 1]; ++r) {
      ASSERT_LT(got.runs[r - 1].end, got.runs[r].begin) << what;
    }
  }
}

TEST(RowRuns, DilationIsTheBoxDilationOfTheMask) {
  const GridGeometry g = small_grid();
  const Mask mask = random_mask(g, 0.01, 3);
  for (int radius : {1, 2, 4}) {
    Mask want(g.num_nodes(), 0);
    for (int k = 0; k < g.dims.z(); ++k) {
      for (int j = 0; j < g.dims.y(); ++j) {
        for (int i = 0; i < g.dims.x(); ++i) {
          if (!mask[g.index(i, j, k)]) continue;
          for (int c = std::max(0, k - radius); c <= std::min(g.dims.z() - 1, k + radius); ++c) {
            for (int b = std::max(0, j - radius); b <= std::min(g.dims.y() - 1, j + radius); ++b) {
              for (int a = std::max(0, i - radius); a <= std::min(g.dims.x() - 1, i + radius); ++a) {
                want[g.index(a, b, c)] = 1;
              }
            }
          }
        }
      }
    }
    expect_equal(dilated(runs_of(g, mask), radius), want, g, "dilated");
  }
}

TEST(RowRuns, ErosionKeepsNodesWhoseInGridBoxIsInTheSet) {
  const GridGeometry g = small_grid();
  const Mask mask = random_mask(g, 0.9, 5);
  Mask want(g.num_nodes(), 0);
  for (int k = 0; k < g.dims.z(); ++k) {
    for (int j = 0; j < g.dims.y(); ++j) {
      for (int i = 0; i < g.dims.x(); ++i) {
        bool all = true;
        for (int c = k - 1; c <= k + 1; ++c) {
          for (int b = j - 1; b <= j + 1; ++b) {
            for (int a = i - 1; a <= i + 1; ++a) {
              if (g.contains(a, b, c) && !mask[g.index(a, b, c)]) all = false;
            }
          }
        }
        want[g.index(i, j, k)] = all;
      }
    }
  }
  std::int64_t kept = 0;
  for (auto v : want) kept += v;
  ASSERT_GT(kept, 10) << "the case must keep some nodes";
  expect_equal(eroded_once(runs_of(g, mask)), want, g, "eroded");
}

TEST(RowRuns, CoarseNodesSitOnOddFineNodes) {
  const GridGeometry g = small_grid();
  const GridGeometry c = g.coarsened();
  const Mask mask = random_mask(g, 0.5, 7);
  Mask want(c.num_nodes(), 0);
  for (int k = 0; k < c.dims.z(); ++k) {
    for (int j = 0; j < c.dims.y(); ++j) {
      for (int i = 0; i < c.dims.x(); ++i) want[c.index(i, j, k)] = mask[g.index(2 * i + 1, 2 * j + 1, 2 * k + 1)];
    }
  }
  expect_equal(coarse_nodes_on(runs_of(g, mask), c.dims), want, c, "coarse");
}

TEST(RowRuns, SampleCellCornersAreTheCornersOfTheCellsHoldingSamples) {
  const GridGeometry g = small_grid();
  const std::vector<Eigen::Vector3f> points = {
      {0.05f, 0.05f, 0.05f}, {1.23f, 0.81f, 0.44f}, {1.26f, 0.83f, 0.41f}, {2.19f, 1.59f, 1.19f}};
  Mask want(g.num_nodes(), 0);
  for (const auto& p : points) {
    const Eigen::Vector3i c = (p.cast<double>() / g.spacing).array().floor().cast<int>();
    for (int q = 0; q < 8; ++q) {
      const int i = c.x() + (q & 1), j = c.y() + ((q >> 1) & 1), k = c.z() + (q >> 2);
      if (g.contains(i, j, k)) want[g.index(i, j, k)] = 1;
    }
  }
  expect_equal(sample_cell_corners(g, points), want, g, "corners");
}

}  // namespace
}  // namespace hos::recon
