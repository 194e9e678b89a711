// recon/grid.* and recon/vector_field.*.
#include "recon/grid.h"

#include <gtest/gtest.h>

#include "recon/vector_field.h"

namespace hos::recon {
namespace {

TEST(Grid, AdmissibleDimsCoarsenToTheRequestedDepth) {
  for (int n : {17, 64, 100}) {
    const int d = admissible_dims(n, 4);
    EXPECT_GE(d, n);
    GridGeometry g;
    g.dims = Eigen::Vector3i::Constant(d);
    for (int level = 1; level < 4; ++level) {
      ASSERT_TRUE(g.can_coarsen(1)) << n;
      const GridGeometry c = g.coarsened();
      // Coarse node I sits on fine node 2I + 1.
      EXPECT_TRUE(c.position(2, 3, 4).isApprox(g.position(5, 7, 9)));
      g = c;
    }
  }
}

TEST(Grid, TrilinearSampleIsExactForLinearFunctions) {
  GridGeometry g;
  g.dims = Eigen::Vector3i(7, 8, 9);
  g.spacing = 0.5;
  g.origin = Eigen::Vector3d(1, 2, 3);
  ScalarGrid f(g);
  const auto linear = [](const Eigen::Vector3d& p) { return 2 * p.x() - p.y() + 0.5 * p.z(); };
  for (int k = 0; k < 9; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 7; ++i) f.values[g.index(i, j, k)] = linear(g.position(i, j, k));
  const Eigen::Vector3d p(2.3, 3.1, 5.7);
  EXPECT_NEAR(f.sample(p), linear(p), 1e-12);
}

TEST(VectorField, SplatConservesMassAndDivergenceOfLinearFieldIsExact) {
  GridGeometry g;
  g.dims = Eigen::Vector3i::Constant(9);
  g.spacing = 0.25;
  VectorGrid splat = splat_normals(g, {Eigen::Vector3f(1.1f, 0.9f, 1.3f)}, {Eigen::Vector3f(0, 0, 2)}, {});
  double total = 0.0;
  for (double v : splat.components[2]) total += v;
  EXPECT_NEAR(total, 2.0, 1e-6);

  VectorGrid field{g, {}};
  for (auto& c : field.components) c.assign(g.num_nodes(), 0.0);
  for (int k = 0; k < 9; ++k)
    for (int j = 0; j < 9; ++j)
      for (int i = 0; i < 9; ++i) {
        const Eigen::Vector3d p = g.position(i, j, k);
        field.components[0][g.index(i, j, k)] = 3.0 * p.x();
        field.components[1][g.index(i, j, k)] = -1.0 * p.y();
      }
  const ScalarGrid div = divergence(field);
  EXPECT_NEAR(div.values[g.index(4, 4, 4)], 2.0, 1e-9);
}

}  // namespace
}  // namespace hos::recon
