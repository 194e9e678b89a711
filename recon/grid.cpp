#include "recon/grid.h"

#include <cmath>
#include <cstdint>

#include "core/huge_pages.h"

namespace hos::recon {

GridGeometry GridGeometry::coarsened() const {
  GridGeometry c;
  c.dims = (dims.array() - 1) / 2;
  c.spacing = 2.0 * spacing;
  c.origin = origin + Eigen::Vector3d::Constant(spacing);
  return c;
}

bool GridGeometry::can_coarsen(int min_nodes) const {
  for (int a = 0; a < 3; ++a) {
    if ((dims[a] + 1) % 2 != 0 || (dims[a] - 1) / 2 < min_nodes) return false;
  }
  return true;
}

int admissible_dims(int n, int levels) {
  const int step = 1 << (levels - 1);
  const int m = (n + 1 + step - 1) / step;
  return m * step - 1;
}

namespace {

template <typename T>
void assign_large_impl(std::vector<T>& v, std::size_t n, T value) {
  constexpr std::size_t kHuge = std::size_t{2} << 20;
  if (n * sizeof(T) >= 4 * kHuge && v.capacity() < n) {
    std::vector<T>().swap(v);
    v.reserve(n);
    advise_huge_pages(v);  // before anything touches it
  }
  v.assign(n, value);
}

}  // namespace

void assign_large(std::vector<double>& v, std::size_t n, double value) { assign_large_impl(v, n, value); }
void assign_large(std::vector<float>& v, std::size_t n, float value) { assign_large_impl(v, n, value); }

TrilinearStencil trilinear_stencil(const GridGeometry& g, const Eigen::Vector3d& x) {
  const Eigen::Vector3d u = g.to_grid(x);
  TrilinearStencil s;
  for (int a = 0; a < 3; ++a) {
    const double fl = std::floor(u[a]);
    s.corner[a] = static_cast<int>(fl);
    s.frac[a] = u[a] - fl;
  }
  return s;
}

double sample_trilinear(const GridGeometry& g, const std::vector<double>& values, const Eigen::Vector3d& x) {
  double v = 0.0;
  for_each_trilinear_corner(g, x, [&](int i, int j, int k, double w) { v += w * values[g.index(i, j, k)]; });
  return v;
}

}  // namespace hos::recon
