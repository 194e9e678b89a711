// recon/active_nodes.*: the band of a banded solve, its coarsening, and the
// banded operator and transfers built on it.
#include "recon/active_nodes.h"

#include <gtest/gtest.h>

#include <cmath>

#include "recon/energy_operator.h"
#include "recon/grid_transfer.h"
#include "tests/recon/shape_samples.h"

namespace hos::recon {
namespace {

using testing::cube_grid;

// Points on a sphere of radius r around the grid's centre.
std::vector<Eigen::Vector3f> sphere_points(const GridGeometry& g, double r, int n) {
  const Eigen::Vector3d c = g.position(g.dims.x() / 2, g.dims.y() / 2, g.dims.z() / 2);
  std::vector<Eigen::Vector3f> points;
  for (int s = 0; s < n; ++s) {
    const double z = 1.0 - 2.0 * (s + 0.5) / n, phi = 2.399963 * s;  // golden-angle spiral
    const double rho = std::sqrt(1.0 - z * z);
    points.push_back((c + r * Eigen::Vector3d(rho * std::cos(phi), rho * std::sin(phi), z)).cast<float>());
  }
  return points;
}

TEST(ActiveNodes, BandHoldsExactlyTheNodesNearTheSamples) {
  const GridGeometry g = cube_grid(47, 1.0);
  const auto points = sphere_points(g, 15.0, 20000);
  const int voxels = 3;
  const ActiveNodes band = band_around_samples(g, points, voxels);
  ASSERT_FALSE(band.is_all());
  const Eigen::Vector3d c = g.position(23, 23, 23);
  std::int64_t counted = 0;
  for (int k = 0; k < g.dims.z(); ++k) {
    for (int j = 0; j < g.dims.y(); ++j) {
      for (int i = 0; i < g.dims.x(); ++i) {
        const double d = std::abs((g.position(i, j, k) - c).norm() - 15.0);
        const bool active = band.contains(g.index(i, j, k));
        counted += active;
        // A node within `voxels` per axis of a sample cell's corner is at most
        // (voxels + 1) * sqrt(3) from the sample; a node within voxels of the
        // sphere is within voxels per axis of some sample's cell (dense samples).
        if (d > (voxels + 1) * std::sqrt(3.0)) {
          EXPECT_FALSE(active) << i << " " << j << " " << k;
        }
        if (d < voxels) {
          EXPECT_TRUE(active) << i << " " << j << " " << k;
        }
      }
    }
  }
  EXPECT_EQ(counted, band.count());
  std::int64_t in_spans = 0;
  for (const NodeSpan& s : band.spans()) {
    in_spans += s.end - s.begin;
    for (int i = s.begin; i < s.end; ++i) EXPECT_TRUE(band.contains(g.index(i, s.j, s.k)));
  }
  EXPECT_EQ(in_spans, band.count());
}

TEST(ActiveNodes, CoarseBandLiesInsideTheFineBand) {
  const GridGeometry fine = cube_grid(47, 1.0);
  const GridGeometry coarse = fine.coarsened();
  const ActiveNodes band = band_around_samples(fine, sphere_points(fine, 15.0, 20000), 4);
  const ActiveNodes coarse_band = band.coarsened(fine, coarse);
  EXPECT_GT(coarse_band.count(), 0);
  EXPECT_LT(coarse_band.count(), band.count() / 4);
  // Every fine neighbour of an active coarse node is active: the coarse
  // correction never reaches past the fine band's Dirichlet boundary.
  for (const NodeSpan& s : coarse_band.spans()) {
    for (int i = s.begin; i < s.end; ++i) {
      for (int o = 0; o < 27; ++o) {
        const int fi = 2 * i + 1 + o % 3 - 1, fj = 2 * s.j + 1 + (o / 3) % 3 - 1, fk = 2 * s.k + 1 + o / 9 - 1;
        ASSERT_TRUE(band.contains(fine.index(fi, fj, fk)));
      }
    }
  }
}

TEST(ActiveNodes, BandStoresItsNodesAndTheirHaloCompactly) {
  const GridGeometry g = cube_grid(31, 0.1);
  const ActiveNodes band = band_around_samples(g, sphere_points(g, 1.0, 5000), 2);
  ASSERT_FALSE(band.is_all());
  // Every node's dense index, gathered into the band's layout.
  std::vector<double> dense(g.num_nodes()), stored(band.storage_size(), -1.0);
  for (std::int64_t n = 0; n < g.num_nodes(); ++n) dense[n] = static_cast<double>(n);
  band.gather(dense.data(), stored.data());
  const int h = ActiveNodes::kHalo;
  std::int64_t near_count = 0;
  for (int k = 0; k < g.dims.z(); ++k) {
    for (int j = 0; j < g.dims.y(); ++j) {
      for (int i = 0; i < g.dims.x(); ++i) {
        bool near = false;  // an active node within kHalo along every axis
        for (int dz = -h; dz <= h && !near; ++dz) {
          for (int dy = -h; dy <= h && !near; ++dy) {
            for (int dx = -h; dx <= h && !near; ++dx) {
              near = g.contains(i + dx, j + dy, k + dz) && band.contains(g.index(i + dx, j + dy, k + dz));
            }
          }
        }
        near_count += near;
        const std::int64_t base = band.row_base(j, k, i);
        if (!near) {
          ASSERT_EQ(base, ActiveNodes::kNotStored) << i << " " << j << " " << k;
          continue;
        }
        ASSERT_NE(base, ActiveNodes::kNotStored) << i << " " << j << " " << k;
        ASSERT_EQ(stored[base + i], dense[g.index(i, j, k)]) << i << " " << j << " " << k;
      }
    }
  }
  EXPECT_EQ(near_count, band.storage_size());
  EXPECT_LT(band.storage_size(), g.num_nodes());
  // A row gathered back: stored values where stored, zeros elsewhere.
  const int j = g.dims.y() / 2, k = g.dims.z() / 2;
  std::vector<double> row(g.dims.x());
  band.gather_row(stored.data(), j, k, 0, g.dims.x(), row.data());
  for (int i = 0; i < g.dims.x(); ++i) {
    EXPECT_EQ(row[i], band.row_base(j, k, i) == ActiveNodes::kNotStored ? 0.0 : dense[g.index(i, j, k)]);
  }
  // Scattering writes exactly the active nodes.
  std::vector<double> back(g.num_nodes(), -1.0);
  band.scatter_active(stored.data(), back.data());
  for (std::int64_t n = 0; n < g.num_nodes(); ++n) {
    ASSERT_EQ(back[n], band.contains(n) ? dense[n] : -1.0) << n;
  }
}

// The residual of a screened operator restricted to the band around `count`
// samples matches the dense operator's on the band's rows and writes nothing
// else.
void check_banded_operator_rows(int count, bool per_cell) {
  const GridGeometry g = cube_grid(31, 0.1);
  const auto points = std::make_shared<const std::vector<Eigen::Vector3f>>(sphere_points(g, 1.0, count));
  EnergyOperator dense(g, SmoothnessEnergy::kFullHessian, 0.3);
  dense.set_screening(points, 50.0);
  ASSERT_EQ(dense.screening().kept_per_cell(), per_cell) << count;
  EnergyOperator banded = dense;
  auto band = std::make_shared<const ActiveNodes>(band_around_samples(g, *points, 2));
  banded.set_active(band);
  std::vector<double> x(g.num_nodes()), b(g.num_nodes(), 1.0);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.37 * i);
  std::vector<double> r_dense(g.num_nodes(), 7.0);
  dense.residual(b.data(), x.data(), r_dense.data());
  // The same x and b in the band's layout: the active rows must match the
  // dense operator's (they read x in the halo), nothing else is written.
  std::vector<double> xb(band->storage_size()), bb(band->storage_size()), rb(band->storage_size(), 7.0);
  band->gather(x.data(), xb.data());
  band->gather(b.data(), bb.data());
  banded.residual(bb.data(), xb.data(), rb.data());
  std::vector<double> r_band(g.num_nodes(), 7.0);
  band->scatter_active(rb.data(), r_band.data());
  for (std::int64_t n = 0; n < g.num_nodes(); ++n) {
    if (band->contains(n)) {
      ASSERT_NEAR(r_band[n], r_dense[n], 1e-12 * std::abs(r_dense[n]) + 1e-12) << count << " samples, band row " << n;
    }
  }
  std::int64_t written = 0;
  for (double v : rb) written += v != 7.0;
  EXPECT_LE(written, band->count()) << count << " samples: entries of the halo were written";
}

TEST(ActiveNodes, BandedOperatorComputesTheBandRowsOnly) {
  // The screening term in both its forms: 5000 samples keep it per touched
  // node, 300 (about one per cell) per cell.
  for (const auto& [count, per_cell] : {std::pair{5000, false}, std::pair{300, true}}) {
    check_banded_operator_rows(count, per_cell);
  }
}

TEST(ActiveNodes, TotalVariationOperatorRefusesABand) {
  const GridGeometry g = cube_grid(31, 0.1);
  EnergyOperator tv(g, SmoothnessEnergy::kTotalVariation, 0.0, std::vector<double>(g.num_nodes(), 1.0), 0.1);
  auto band = std::make_shared<const ActiveNodes>(band_around_samples(g, sphere_points(g, 1.0, 5000), 2));
  EXPECT_THROW(tv.set_active(band), std::invalid_argument);
}

TEST(ActiveNodes, BandedTransfersMatchTheDenseOnesAndStayAdjoint) {
  const GridGeometry fine = cube_grid(31, 0.1);
  const GridGeometry coarse = fine.coarsened();
  const ActiveNodes band = band_around_samples(fine, sphere_points(fine, 1.0, 5000), 3);
  const ActiveNodes coarse_band = band.coarsened(fine, coarse);
  // Vectors that are zero outside their bands, as in the V-cycle.
  std::vector<double> r(fine.num_nodes(), 0.0), e(coarse.num_nodes(), 0.0);
  for (std::int64_t i = 0; i < fine.num_nodes(); ++i) r[i] = band.contains(i) ? std::sin(0.37 * i) : 0.0;
  for (std::int64_t i = 0; i < coarse.num_nodes(); ++i) e[i] = coarse_band.contains(i) ? std::cos(0.91 * i) : 0.0;
  std::vector<double> rc_dense, pe_dense(fine.num_nodes(), 0.0);
  restrict_to_coarse(fine, r, coarse, rc_dense);
  prolongate_add(coarse, e, fine, pe_dense);
  // The same in the bands' layouts.
  std::vector<double> rb(band.storage_size()), eb(coarse_band.storage_size());
  band.gather(r.data(), rb.data());
  coarse_band.gather(e.data(), eb.data());
  std::vector<double> rcb(coarse_band.storage_size(), 0.0), peb(band.storage_size(), 0.0);
  restrict_to_coarse(fine, band, rb.data(), coarse, coarse_band, rcb.data());
  prolongate_add(coarse, coarse_band, eb.data(), fine, band, peb.data());
  std::vector<double> rc(coarse.num_nodes(), 0.0), pe(fine.num_nodes(), 0.0);
  coarse_band.scatter_active(rcb.data(), rc.data());
  band.scatter_active(peb.data(), pe.data());
  double lhs = 0, rhs = 0;
  for (std::int64_t i = 0; i < coarse.num_nodes(); ++i) {
    if (coarse_band.contains(i)) {
      EXPECT_NEAR(rc[i], rc_dense[i], 1e-12);
    }
    lhs += 8.0 * rc[i] * e[i];
  }
  for (std::int64_t i = 0; i < fine.num_nodes(); ++i) {
    if (band.contains(i)) {
      EXPECT_NEAR(pe[i], pe_dense[i], 1e-12);
    }
    rhs += r[i] * pe[i];
  }
  EXPECT_NEAR(lhs, rhs, 1e-9 * std::abs(rhs));

  // From a whole coarse grid to every stored node (active and halo): the
  // dense prolongation, gathered.
  std::vector<double> e_all(coarse.num_nodes());
  for (std::int64_t i = 0; i < coarse.num_nodes(); ++i) e_all[i] = std::cos(0.91 * i);
  std::vector<double> dense(fine.num_nodes(), 0.0), expected(band.storage_size()), stored(band.storage_size(), 0.0);
  prolongate_add(coarse, e_all, fine, dense);
  band.gather(dense.data(), expected.data());
  prolongate_add_to_stored(coarse, ActiveNodes::all(coarse), e_all.data(), band, stored.data());
  for (std::int64_t i = 0; i < band.storage_size(); ++i) ASSERT_NEAR(stored[i], expected[i], 1e-12) << i;
}

}  // namespace
}  // namespace hos::recon
