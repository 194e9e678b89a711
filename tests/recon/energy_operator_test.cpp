// recon/energy_operator.*: the stencils of paper eq. (9) on polynomials.
#include "recon/energy_operator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "recon/grid_transfer.h"
#include "tests/recon/shape_samples.h"

namespace hos::recon {
namespace {

using testing::cube_grid;

std::vector<double> sample(const GridGeometry& g, double (*f)(const Eigen::Vector3d&)) {
  std::vector<double> v(g.num_nodes());
  for (int k = 0; k < g.dims.z(); ++k)
    for (int j = 0; j < g.dims.y(); ++j)
      for (int i = 0; i < g.dims.x(); ++i) v[g.index(i, j, k)] = f(g.position(i, j, k));
  return v;
}

TEST(EnergyOperator, MembraneIsMinusLaplacianOnQuadratics) {
  const GridGeometry g = cube_grid(11, 0.1);
  const EnergyOperator op(g, SmoothnessEnergy::kMembrane, 0.0);
  const auto f = sample(g, [](const Eigen::Vector3d& p) { return p.x() * p.x() + 2 * p.y() * p.z(); });
  std::vector<double> y;
  op.apply(f, y);
  EXPECT_NEAR(y[g.index(5, 5, 5)], -2.0, 1e-9);  // -(2 + 0 + 0)
}

TEST(EnergyOperator, HessianTermVanishesOnQuadraticsAndMeasuresQuartics) {
  const GridGeometry g = cube_grid(13, 0.1);
  const double w = 0.5;
  // A = -Lap + 2 w H; on x^2 y^2 at the centre: H f = d^4f/dx^4 + ... + 2 * 2 * (fxy)_xy...
  const EnergyOperator full(g, SmoothnessEnergy::kFullHessian, w);
  const EnergyOperator membrane_only(g, SmoothnessEnergy::kFullHessian, 0.0);
  const auto quadratic = sample(g, [](const Eigen::Vector3d& p) { return p.x() * p.y() + p.z() * p.z(); });
  std::vector<double> a, b;
  full.apply(quadratic, a);
  membrane_only.apply(quadratic, b);
  EXPECT_NEAR(a[g.index(6, 6, 6)], b[g.index(6, 6, 6)], 1e-8) << "second derivatives are constant";

  // f = x^4: fxxxx = 24, so the pure-second part of H gives 24 (discretely exact).
  const auto quartic = sample(g, [](const Eigen::Vector3d& p) { return std::pow(p.x(), 4); });
  const EnergyOperator pure(g, SmoothnessEnergy::kPureSecond, w);
  const EnergyOperator lap(g, SmoothnessEnergy::kPureSecond, 0.0);
  pure.apply(quartic, a);
  lap.apply(quartic, b);
  EXPECT_NEAR((a[g.index(6, 6, 6)] - b[g.index(6, 6, 6)]) / (2 * w), 24.0, 1e-6);
}

TEST(EnergyOperator, IsSymmetric) {
  const GridGeometry g = cube_grid(9, 0.2);
  std::vector<double> tv_weights(g.num_nodes());
  for (std::size_t i = 0; i < tv_weights.size(); ++i) tv_weights[i] = 1.0 + (i % 7) * 0.3;
  for (const auto& op : {EnergyOperator(g, SmoothnessEnergy::kFullHessian, 0.3),
                         EnergyOperator(g, SmoothnessEnergy::kTotalVariation, 0.0, tv_weights, 0.7)}) {
    std::vector<double> x(g.num_nodes()), y(g.num_nodes()), ax, ay;
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(1.3 * i), y[i] = std::cos(0.7 * i);
    op.apply(x, ax);
    op.apply(y, ay);
    double xay = 0, yax = 0;
    for (std::size_t i = 0; i < x.size(); ++i) xay += x[i] * ay[i], yax += y[i] * ax[i];
    EXPECT_NEAR(xay, yax, 1e-9 * std::abs(xay));
  }
}

TEST(EnergyOperator, ScreeningAddsTheSumOverSamplesOfSquaredTrilinearValues) {
  // Samples everywhere in the grid, also in the cells at its faces and in the
  // ghost cells just outside (whose outer corners are the zero ghost nodes).
  // The term's two forms: 3000 samples in the 125 cells of 4^3 nodes (per
  // touched node); 400 in the 1000 cells of 9^3 nodes, 300 pairs of samples
  // in the 9261 cells of 20^3 nodes and 150 single ones in them (per cell,
  // the pairs by their moments, the single ones by their weights).
  struct Case {
    int n, count;
    bool pairs, per_cell;
  };
  for (const Case& t : {Case{4, 3000, false, false}, Case{9, 400, false, true}, Case{20, 300, true, true},
                        Case{20, 150, false, true}}) {
    const int n = t.n;
    const GridGeometry g = cube_grid(n, 0.1);
    auto points = std::make_shared<std::vector<Eigen::Vector3f>>();
    for (int s = 0; s < t.count; ++s) {
      const Eigen::Vector3d u(std::fmod(0.37 * s, 1.0), std::fmod(0.61 * s, 1.0), std::fmod(0.83 * s, 1.0));
      const Eigen::Vector3f p = (-0.1 + 0.1 * (n + 1) * u.array()).matrix().cast<float>();  // [-h, n h] per axis
      points->push_back(p);
      if (t.pairs) points->push_back(p + Eigen::Vector3f::Constant(1e-4f));
    }
    const double weight = 2.5;
    const EnergyOperator plain(g, SmoothnessEnergy::kMembrane, 0.0);
    EnergyOperator screened = plain;
    screened.set_screening(points, weight);
    EXPECT_EQ(screened.screening().kept_per_cell(), t.per_cell) << n << " " << t.count;
    std::vector<double> x(g.num_nodes()), a, b;
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.7 * i) + 0.3;
    plain.apply(x, a);
    screened.apply(x, b);
    // weight * S^T S x with (S x)_s = f(p_s), trilinear, ghost nodes zero;
    // its l1 row sums weight * sum_s w_s(node), the weights being >= 0 and
    // summing to 1 per sample.
    std::vector<double> expected(g.num_nodes(), 0.0), expected_l1(g.num_nodes(), 0.0);
    ScalarGrid f(g);
    f.values = x;
    for (const auto& p : *points) {
      const double value = f.sample(p.cast<double>());
      const TrilinearStencil st = trilinear_stencil(g, p.cast<double>());
      for (int c = 0; c < 8; ++c) {
        const Eigen::Vector3i node = st.corner + Eigen::Vector3i(c & 1, (c >> 1) & 1, c >> 2);
        if (g.contains(node.x(), node.y(), node.z())) {
          const double w = st.weight(c & 1, (c >> 1) & 1, c >> 2);
          expected[g.index(node.x(), node.y(), node.z())] += weight * w * value;
          expected_l1[g.index(node.x(), node.y(), node.z())] += weight * w;
        }
      }
    }
    std::vector<double> l1_plain(g.num_nodes()), l1_screened(g.num_nodes());
    plain.l1_diagonals(l1_plain.data());
    screened.l1_diagonals(l1_screened.data());
    for (std::int64_t i = 0; i < g.num_nodes(); ++i) {
      ASSERT_NEAR(b[i] - a[i], expected[i], 1e-5 * (1.0 + std::abs(expected[i]))) << n << " " << i;
      ASSERT_NEAR(l1_screened[i] - l1_plain[i], expected_l1[i], 1e-5 * (1.0 + expected_l1[i])) << n << " " << i;
    }
  }
}

TEST(EnergyOperator, TransferOperatorsAreAdjointUpToTheVolumeFactor) {
  GridGeometry fine = cube_grid(15, 0.1);
  const GridGeometry coarse = fine.coarsened();
  ASSERT_EQ(coarse.dims, Eigen::Vector3i::Constant(7));
  std::vector<double> r(fine.num_nodes()), e(coarse.num_nodes()), rc, pe(fine.num_nodes(), 0.0);
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = std::sin(0.37 * i);
  for (std::size_t i = 0; i < e.size(); ++i) e[i] = std::cos(0.91 * i);
  restrict_to_coarse(fine, r, coarse, rc);
  prolongate_add(coarse, e, fine, pe);
  double lhs = 0, rhs = 0;
  for (std::size_t i = 0; i < e.size(); ++i) lhs += 8.0 * rc[i] * e[i];
  for (std::size_t i = 0; i < r.size(); ++i) rhs += r[i] * pe[i];
  EXPECT_NEAR(lhs, rhs, 1e-9 * std::abs(rhs));
}

}  // namespace
}  // namespace hos::recon
