#include "recon/vector_field.h"

#include <cmath>

namespace hos::recon {
namespace {

// out is scratch space of v's size, reused across calls: allocating (and
// page-faulting) a grid-sized buffer per pass dominated the filter's time.
void box_filter_axis(const GridGeometry& g, std::vector<double>& v, std::vector<double>& out, int axis) {
  const Eigen::Vector3i d = g.dims;
  out.resize(v.size());
  const std::int64_t stride = axis == 0 ? 1 : axis == 1 ? d.x() : std::int64_t{d.x()} * d.y();
  const int n = d[axis];
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < d.z(); ++k) {
    for (int j = 0; j < d.y(); ++j) {
      for (int i = 0; i < d.x(); ++i) {
        const Eigen::Vector3i p(i, j, k);
        const std::int64_t idx = g.index(i, j, k);
        double s = v[idx];
        if (p[axis] > 0) s += v[idx - stride];
        if (p[axis] < n - 1) s += v[idx + stride];
        out[idx] = s / 3.0;
      }
    }
  }
  v.swap(out);
}

}  // namespace

VectorGrid splat_normals(const GridGeometry& geometry, const std::vector<Eigen::Vector3f>& points,
                         const std::vector<Eigen::Vector3f>& normals,
                         const std::vector<float>& weights) {
  VectorGrid field{geometry, {}};
  for (auto& c : field.components) c.assign(geometry.num_nodes(), 0.0);
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
  std::vector<double> scratch;
  for (int pass = 0; pass < passes; ++pass) {
    for (int axis = 0; axis < 3; ++axis) box_filter_axis(geometry, values, scratch, axis);
  }
}

void box_filter(VectorGrid& field, int passes) {
  for (auto& c : field.components) box_filter(field.geometry, c, passes);
}

std::vector<double> splat_density(const GridGeometry& geometry, const std::vector<Eigen::Vector3f>& points,
                                  const std::vector<float>& weights) {
  std::vector<double> density(geometry.num_nodes(), 0.0);
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

void normalize_field(VectorGrid& field, const std::vector<Eigen::Vector3f>& points,
                     int filter_passes) {
  double sum = 0.0;
  std::size_t count = 0;
  std::array<ScalarGrid, 3> comp;
  for (int a = 0; a < 3; ++a) {
    comp[a].geometry = field.geometry;
    comp[a].values = field.components[a];
  }
  // A subset of the samples suffices for a mean.
  const std::size_t step = std::max<std::size_t>(1, points.size() / 20000);
  for (std::size_t p = 0; p < points.size(); p += step) {
    const Eigen::Vector3d x = points[p].cast<double>();
    const Eigen::Vector3d f(comp[0].sample(x), comp[1].sample(x), comp[2].sample(x));
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
    for (double& v : c) v *= scale;
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
