#include "recon/vector_field.h"

#include <algorithm>
#include <cmath>

namespace hos::recon {
namespace {

// One pass of [1 1 1] / 3 along lines of n values, each line's t-th value at
// in + t * m (m interleaved lines, contiguous): vectorises along the lines.
// Values beyond the line's ends are zero.
void box_pass(const double* __restrict in, double* __restrict out, int n, int m) {
  constexpr double third = 1.0 / 3.0;
  for (int t = 0; t < n; ++t) {
    const double* c = in + std::int64_t{t} * m;
    double* o = out + std::int64_t{t} * m;
    const bool lo = t > 0, hi = t < n - 1;
    for (int q = 0; q < m; ++q) {
      o[q] = (c[q] + (lo ? c[q - m] : 0.0) + (hi ? c[q + m] : 0.0)) * third;
    }
  }
}

// All passes along one axis while the lines stay in cache: the 1-D filters
// along different axes commute, so x, y, z passes may be grouped per axis.
void box_filter_axis(const GridGeometry& g, std::vector<double>& v, int axis, int passes) {
  const Eigen::Vector3i d = g.dims;
  const std::int64_t plane = std::int64_t{d.x()} * d.y();
  // A slab: n values along the axis times m interleaved lines.
  const int n = d[axis];
  const int m = axis == 0 ? 1 : d.x();
  const int slabs = axis == 0 ? d.y() * d.z() : axis == 1 ? d.z() : d.y();
  const std::int64_t stride = axis == 0 ? 1 : axis == 1 ? d.x() : plane;
#pragma omp parallel
  {
    std::vector<double> a(std::int64_t{n} * m), b(a.size());
#pragma omp for schedule(static)
    for (int s = 0; s < slabs; ++s) {
      // First value of the slab: row s (x), plane s (y) or row s of plane 0 (z).
      double* base = v.data() + (axis == 0 ? std::int64_t{s} * d.x() : axis == 1 ? s * plane : std::int64_t{s} * d.x());
      for (int t = 0; t < n; ++t) std::copy(base + t * stride, base + t * stride + m, a.data() + std::int64_t{t} * m);
      for (int p = 0; p < passes; ++p) {
        box_pass(a.data(), b.data(), n, m);
        a.swap(b);
      }
      for (int t = 0; t < n; ++t) std::copy(a.data() + std::int64_t{t} * m, a.data() + std::int64_t{t + 1} * m, base + t * stride);
    }
  }
}

}  // namespace

VectorGrid splat_normals(const GridGeometry& geometry, const std::vector<Eigen::Vector3f>& points,
                         const std::vector<Eigen::Vector3f>& normals,
                         const std::vector<float>& weights) {
  VectorGrid field{geometry, {}};
  for (auto& c : field.components) assign_large(c, geometry.num_nodes());
  for (std::size_t p = 0; p < points.size(); ++p) {
    const Eigen::Vector3d n = normals[p].cast<double>() * (weights.empty() ? 1.0 : weights[p]);
    const TrilinearStencil s = trilinear_stencil(geometry, points[p].cast<double>());
    for (int oz = 0; oz < 2; ++oz) {
      for (int oy = 0; oy < 2; ++oy) {
        for (int ox = 0; ox < 2; ++ox) {
          const int i = s.corner.x() + ox, j = s.corner.y() + oy, k = s.corner.z() + oz;
          if (!geometry.contains(i, j, k)) continue;
          const double w = s.weight(ox, oy, oz);
          const std::int64_t idx = geometry.index(i, j, k);
          for (int a = 0; a < 3; ++a) field.components[a][idx] += w * n[a];
        }
      }
    }
  }
  return field;
}

void box_filter(const GridGeometry& geometry, std::vector<double>& values, int passes) {
  if (passes <= 0) return;
  for (int axis = 0; axis < 3; ++axis) box_filter_axis(geometry, values, axis, passes);
}

void box_filter(VectorGrid& field, int passes) {
  for (auto& c : field.components) box_filter(field.geometry, c, passes);
}

std::vector<double> splat_density(const GridGeometry& geometry, const std::vector<Eigen::Vector3f>& points,
                                  const std::vector<float>& weights) {
  std::vector<double> density;
  assign_large(density, geometry.num_nodes());
  for (std::size_t p = 0; p < points.size(); ++p) {
    const double w = weights.empty() ? 1.0 : weights[p];
    const TrilinearStencil s = trilinear_stencil(geometry, points[p].cast<double>());
    for (int oz = 0; oz < 2; ++oz) {
      for (int oy = 0; oy < 2; ++oy) {
        for (int ox = 0; ox < 2; ++ox) {
          const int i = s.corner.x() + ox, j = s.corner.y() + oy, k = s.corner.z() + oz;
          if (geometry.contains(i, j, k)) density[geometry.index(i, j, k)] += w * s.weight(ox, oy, oz);
        }
      }
    }
  }
  return density;
}

void use_density_magnitude(VectorGrid& field, const std::vector<double>& density) {
  const std::int64_t n = field.geometry.num_nodes();
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    const Eigen::Vector3d f(field.components[0][i], field.components[1][i], field.components[2][i]);
    const double len = f.norm();
    // Where opposite orientations cancel (thin parts), keep the field as is.
    const double scale = len > 1e-3 * density[i] ? density[i] / len : 1.0;
    for (int a = 0; a < 3; ++a) field.components[a][i] *= scale;
  }
}

VectorGrid density_scaled_field(const GridGeometry& geometry, const std::vector<Eigen::Vector3f>& points,
                                const std::vector<Eigen::Vector3f>& normals,
                                const std::vector<float>& weights, int density_passes,
                                int direction_passes) {
  std::vector<double> density = splat_density(geometry, points, weights);
  box_filter(geometry, density, density_passes);
  if (direction_passes % 4 != 0 || !geometry.can_coarsen(3)) {
    VectorGrid field = splat_normals(geometry, points, normals, weights);
    box_filter(field, direction_passes);
    use_density_magnitude(field, density);
    return field;
  }
  const GridGeometry coarse = geometry.coarsened();
  VectorGrid directions = splat_normals(coarse, points, normals, weights);
  box_filter(directions, direction_passes / 4);
  // The coarse density tells where opposite orientations cancel.
  std::vector<double> coarse_density = splat_density(coarse, points, weights);
  box_filter(coarse, coarse_density, direction_passes / 4);

  VectorGrid field{geometry, {}};
  for (auto& c : field.components) assign_large(c, geometry.num_nodes());
  const Eigen::Vector3i d = geometry.dims;
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < d.z(); ++k) {
    for (int j = 0; j < d.y(); ++j) {
      for (int i = 0; i < d.x(); ++i) {
        const std::int64_t n = geometry.index(i, j, k);
        if (density[n] == 0.0) continue;
        const Eigen::Vector3d x = geometry.position(i, j, k);
        Eigen::Vector3d v;
        for (int a = 0; a < 3; ++a) v[a] = sample_trilinear(coarse, directions.components[a], x);
        const double len = v.norm(), mass = sample_trilinear(coarse, coarse_density, x);
        // As in use_density_magnitude: where orientations cancel (thin parts),
        // keep the smoothed sum, here relative to the coarse density.
        const double scale = len > 1e-3 * mass ? density[n] / len : mass > 0.0 ? density[n] / mass : 0.0;
        const Eigen::Vector3d f = scale * v;
        for (int a = 0; a < 3; ++a) field.components[a][n] = f[a];
      }
    }
  }
  return field;
}

void normalize_field(VectorGrid& field, const std::vector<Eigen::Vector3f>& points,
                     int filter_passes) {
  double sum = 0.0;
  std::size_t count = 0;
  // A subset of the samples suffices for a mean.
  const std::size_t step = std::max<std::size_t>(1, points.size() / 20000);
  for (std::size_t p = 0; p < points.size(); p += step) {
    const Eigen::Vector3d x = points[p].cast<double>();
    Eigen::Vector3d f;
    for (int a = 0; a < 3; ++a) f[a] = sample_trilinear(field.geometry, field.components[a], x);
    sum += f.norm();
    ++count;
  }
  const double mean = count ? sum / static_cast<double>(count) : 0.0;
  if (!(mean > 0.0)) return;
  // The smoothed splat of a surface has a cross-section about (1 + passes)
  // nodes wide; its integral across the surface is mean * width * h.
  const double width = (1.0 + filter_passes) * field.geometry.spacing;
  const double scale = 1.0 / (mean * width);
  for (auto& c : field.components) {
    const std::int64_t n = static_cast<std::int64_t>(c.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) c[i] *= scale;
  }
}

ScalarGrid divergence(const VectorGrid& field) {
  const GridGeometry& g = field.geometry;
  ScalarGrid div(g);
  const double inv2h = 1.0 / (2.0 * g.spacing);
  const Eigen::Vector3i d = g.dims;
  const std::int64_t strides[3] = {1, d.x(), std::int64_t{d.x()} * d.y()};
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < d.z(); ++k) {
    for (int j = 0; j < d.y(); ++j) {
      for (int i = 0; i < d.x(); ++i) {
        const Eigen::Vector3i p(i, j, k);
        const std::int64_t idx = g.index(i, j, k);
        double s = 0.0;
        for (int a = 0; a < 3; ++a) {
          const auto& c = field.components[a];
          const double plus = p[a] < d[a] - 1 ? c[idx + strides[a]] : 0.0;
          const double minus = p[a] > 0 ? c[idx - strides[a]] : 0.0;
          s += (plus - minus) * inv2h;
        }
        div.values[idx] = s;
      }
    }
  }
  return div;
}

}  // namespace hos::recon
