#include "recon/vector_field.h"

#include <algorithm>
#include <array>
#include <cmath>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace hos::recon {
namespace {

// One pass of [1 1 1] / 3 along lines of n values, each line's t-th value at
// in + t * m (m interleaved lines, contiguous): vectorises along the lines.
// Values beyond the line's ends are zero.
template <typename T>
void box_pass(const T* __restrict in, T* __restrict out, int n, int m) {
  constexpr T third = T(1) / T(3);
  for (int t = 0; t < n; ++t) {
    const T* c = in + std::int64_t{t} * m;
    T* o = out + std::int64_t{t} * m;
    const bool lo = t > 0, hi = t < n - 1;
    for (int q = 0; q < m; ++q) {
      o[q] = (c[q] + (lo ? c[q - m] : T(0)) + (hi ? c[q + m] : T(0))) * third;
    }
  }
}

// All passes along one axis while the lines stay in cache: the 1-D filters
// along different axes commute, so x, y, z passes may be grouped per axis.
template <typename T>
void box_filter_axis(const GridGeometry& g, std::vector<T>& v, int axis, int passes) {
  const Eigen::Vector3i d = g.dims;
  const std::int64_t plane = std::int64_t{d.x()} * d.y();
  // A slab: n values along the axis times m interleaved lines.
  const int n = d[axis];
  const int m = axis == 0 ? 1 : d.x();
  const int slabs = axis == 0 ? d.y() * d.z() : axis == 1 ? d.z() : d.y();
  const std::int64_t stride = axis == 0 ? 1 : axis == 1 ? d.x() : plane;
#pragma omp parallel
  {
    std::vector<T> a(std::int64_t{n} * m), b(a.size());
#pragma omp for schedule(static)
    for (int s = 0; s < slabs; ++s) {
      // First value of the slab: row s (x), plane s (y) or row s of plane 0 (z).
      T* base = v.data() + (axis == 0 ? std::int64_t{s} * d.x() : axis == 1 ? s * plane : std::int64_t{s} * d.x());
      for (int t = 0; t < n; ++t) std::copy(base + t * stride, base + t * stride + m, a.data() + std::int64_t{t} * m);
      for (int p = 0; p < passes; ++p) {
        box_pass(a.data(), b.data(), n, m);
        a.swap(b);
      }
      for (int t = 0; t < n; ++t)
        std::copy(a.data() + std::int64_t{t} * m, a.data() + std::int64_t{t + 1} * m, base + t * stride);
    }
  }
}

// Splats value(p) * weight(p) trilinearly onto the stored nodes of `nodes`
// (a sample's corners outside them add nothing).
template <typename T, typename ValueFn>
std::vector<T> splat_stored(const GridGeometry& geometry,
                            const ActiveNodes& nodes,
                            const std::vector<Eigen::Vector3f>& points,
                            const std::vector<float>& weights,
                            ValueFn&& value) {
  std::vector<T> out;
  assign_large(out, static_cast<std::size_t>(nodes.storage_size()));
  for (std::size_t p = 0; p < points.size(); ++p) {
    const double w = (weights.empty() ? 1.0 : weights[p]) * value(p);
    for_each_trilinear_corner(geometry, points[p].cast<double>(), [&](int i, int j, int k, double c) {
      const std::int64_t base = nodes.row_base(j, k, i);
      if (base != ActiveNodes::kNotStored) out[base + i] += static_cast<T>(w * c);
    });
  }
  return out;
}

// The splat of the weights (1 per point if empty).
template <typename T>
std::vector<T> splat_weights(const GridGeometry& geometry,
                             const ActiveNodes& nodes,
                             const std::vector<Eigen::Vector3f>& points,
                             const std::vector<float>& weights) {
  return splat_stored<T>(geometry, nodes, points, weights, [](std::size_t) { return 1.0; });
}

// Central differences in one plane of nodes (zero beyond the grid) times
// factor: fx, fy the x and y components in the plane, fz_below and fz_above
// the z components in the planes below and above (null beyond the grid).
void divergence_plane(const Eigen::Vector3i& d,
                      double factor,
                      const double* fx,
                      const double* fy,
                      const double* fz_below,
                      const double* fz_above,
                      double* out) {
  for (int j = 0; j < d.y(); ++j) {
    for (int i = 0; i < d.x(); ++i) {
      const std::int64_t q = std::int64_t{j} * d.x() + i;
      double s = 0.0;
      s += ((i < d.x() - 1 ? fx[q + 1] : 0.0) - (i > 0 ? fx[q - 1] : 0.0)) * factor;
      s += ((j < d.y() - 1 ? fy[q + d.x()] : 0.0) - (j > 0 ? fy[q - d.x()] : 0.0)) * factor;
      s += ((fz_above ? fz_above[q] : 0.0) - (fz_below ? fz_below[q] : 0.0)) * factor;
      out[q] = s;
    }
  }
}

// The smoothed directions on the grid coarsened once, and the coarse density
// that tells where opposite orientations cancel (density_scaled_field), on
// the stored nodes of `nodes` (every node, or those near the samples).
struct CoarseDirections {
  GridGeometry coarse;
  ActiveNodes nodes;
  std::array<std::vector<double>, 3> directions;
  std::vector<double> density;

  // F at a fine node at x whose smoothed fine density is fine_density.
  Eigen::Vector3d field_at(const Eigen::Vector3d& x, double fine_density) const {
    if (fine_density == 0.0) return Eigen::Vector3d::Zero();
    // Trilinear samples of the directions and the coarse density, as
    // sample_trilinear but with one stencil for the four.
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    double mass = 0.0;
    for_each_trilinear_corner(coarse, x, [&](int i, int j, int k, double w) {
      const std::int64_t base = nodes.row_base(j, k, i);
      if (base == ActiveNodes::kNotStored) return;  // zero: far from every sample
      const std::int64_t n = base + i;
      for (int a = 0; a < 3; ++a) v[a] += w * directions[a][n];
      mass += w * density[n];
    });
    const double len = v.norm();
    // As in use_density_magnitude: where orientations cancel (thin parts),
    // keep the smoothed sum, here relative to the coarse density.
    const double scale = len > 1e-3 * mass ? fine_density / len : mass > 0.0 ? fine_density / mass : 0.0;
    return scale * v;
  }
};

// box_filter on the stored nodes of `nodes`, nodes not stored counting as
// zero: the same values as on the whole grid wherever the stored nodes reach
// `passes` nodes beyond every nonzero value along each axis.
template <typename T>
void box_filter_stored(const GridGeometry& geometry, const ActiveNodes& nodes, std::vector<T>& values, int passes) {
  if (passes <= 0) return;
  if (nodes.is_all()) {
    box_filter(geometry, values, passes);
    return;
  }
  const std::vector<NodeSpan> spans = nodes.stored_spans();
  const std::int64_t n = static_cast<std::int64_t>(spans.size());
  const int nx = geometry.dims.x();
  // Along x: every stored run is a line of its own.
#pragma omp parallel
  {
    std::vector<T> a(nx), b(nx);
#pragma omp for schedule(static)
    for (std::int64_t s = 0; s < n; ++s) {
      const NodeSpan& sp = spans[s];
      const int len = sp.end - sp.begin;
      std::copy(values.data() + sp.first, values.data() + sp.first + len, a.data());
      for (int p = 0; p < passes; ++p) {
        box_pass(a.data(), b.data(), len, 1);
        a.swap(b);
      }
      std::copy(a.data(), a.data() + len, values.data() + sp.first);
    }
  }
  // Along y, then z: one pass at a time over every stored node.
  constexpr T third = T(1) / T(3);
  for (int axis = 1; axis < 3; ++axis) {
    for (int p = 0; p < passes; ++p) {
      const std::vector<T> in(values);
#pragma omp parallel
      {
        std::vector<T> lo(nx), hi(nx);
#pragma omp for schedule(static)
        for (std::int64_t s = 0; s < n; ++s) {
          const NodeSpan& sp = spans[s];
          const int dj = axis == 1, dk = axis == 2;
          nodes.gather_row(in.data(), sp.j - dj, sp.k - dk, sp.begin, sp.end, lo.data());
          nodes.gather_row(in.data(), sp.j + dj, sp.k + dk, sp.begin, sp.end, hi.data());
          const T* c = in.data() + sp.first;
          T* o = values.data() + sp.first;
          for (int t = 0; t < sp.end - sp.begin; ++t) o[t] = (c[t] + lo[t] + hi[t]) * third;
        }
      }
    }
  }
}

// The value stored for node (i, j, k), zero if it is not stored.
template <typename T>
T stored_value(const ActiveNodes& nodes, const std::vector<T>& values, int i, int j, int k) {
  const std::int64_t base = nodes.row_base(j, k, i);
  return base == ActiveNodes::kNotStored ? T(0) : values[base + i];
}

}  // namespace

VectorGrid splat_normals(const GridGeometry& geometry,
                         const std::vector<Eigen::Vector3f>& points,
                         const std::vector<Eigen::Vector3f>& normals,
                         const std::vector<float>& weights) {
  VectorGrid field{geometry, {}};
  const ActiveNodes every_node = ActiveNodes::all(geometry);
  for (int a = 0; a < 3; ++a) {
    field.components[a] = splat_stored<double>(geometry, every_node, points, weights,
                                               [&](std::size_t p) { return static_cast<double>(normals[p][a]); });
  }
  return field;
}

template <typename T>
void box_filter(const GridGeometry& geometry, std::vector<T>& values, int passes) {
  if (passes <= 0) return;
  for (int axis = 0; axis < 3; ++axis) box_filter_axis(geometry, values, axis, passes);
}
template void box_filter<double>(const GridGeometry&, std::vector<double>&, int);
template void box_filter<float>(const GridGeometry&, std::vector<float>&, int);

void box_filter(VectorGrid& field, int passes) {
  for (auto& c : field.components) box_filter(field.geometry, c, passes);
}

std::vector<double> splat_density(const GridGeometry& geometry,
                                  const std::vector<Eigen::Vector3f>& points,
                                  const std::vector<float>& weights) {
  return splat_weights<double>(geometry, ActiveNodes::all(geometry), points, weights);
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

namespace {

// The directions on the grid coarsened once: on every node, or (near) on the
// nodes within reach of the filter around the samples.
CoarseDirections coarse_directions(const GridGeometry& geometry,
                                   const std::vector<Eigen::Vector3f>& points,
                                   const std::vector<Eigen::Vector3f>& normals,
                                   const std::vector<float>& weights,
                                   int direction_passes,
                                   bool near) {
  const GridGeometry coarse = geometry.coarsened();
  const int passes = direction_passes / 4;
  CoarseDirections c{coarse, near ? band_around_samples(coarse, points, passes) : ActiveNodes::all(coarse), {}, {}};
  for (int a = 0; a < 3; ++a) {
    c.directions[a] = splat_stored<double>(coarse, c.nodes, points, weights,
                                           [&](std::size_t p) { return static_cast<double>(normals[p][a]); });
    box_filter_stored(coarse, c.nodes, c.directions[a], passes);
  }
  c.density = splat_weights<double>(coarse, c.nodes, points, weights);
  box_filter_stored(coarse, c.nodes, c.density, passes);
  return c;
}

// Mean |F| over a subset of the samples (a subset suffices for a mean), F
// trilinear from node_field(i, j, k), its value at the 8 nodes around each
// sample (zero beyond the grid).
template <typename NodeField>
double mean_norm_at_samples(const GridGeometry& g,
                            const std::vector<Eigen::Vector3f>& points,
                            const NodeField& node_field) {
  double sum = 0.0;
  std::size_t count = 0;
  const std::size_t step = std::max<std::size_t>(1, points.size() / 20000);
  for (std::size_t p = 0; p < points.size(); p += step) {
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    for_each_trilinear_corner(g, points[p].cast<double>(),
                              [&](int i, int j, int k, double w) { f += w * node_field(i, j, k); });
    sum += f.norm();
    ++count;
  }
  return count ? sum / static_cast<double>(count) : 0.0;
}

// The factor of normalize_field for a mean |F| at the samples (1 if none).
double normalization_scale(const GridGeometry& g, double mean, int filter_passes) {
  if (!(mean > 0.0)) return 1.0;
  // The smoothed splat of a surface has a cross-section about (1 + passes)
  // nodes wide; its integral across the surface is mean * width * h.
  const double width = (1.0 + filter_passes) * g.spacing;
  return 1.0 / (mean * width);
}

}  // namespace

VectorGrid density_scaled_field(const GridGeometry& geometry,
                                const std::vector<Eigen::Vector3f>& points,
                                const std::vector<Eigen::Vector3f>& normals,
                                const std::vector<float>& weights,
                                int density_passes,
                                int direction_passes) {
  std::vector<double> density = splat_density(geometry, points, weights);
  box_filter(geometry, density, density_passes);
  if (direction_passes % 4 != 0 || !geometry.can_coarsen(3)) {
    VectorGrid field = splat_normals(geometry, points, normals, weights);
    box_filter(field, direction_passes);
    use_density_magnitude(field, density);
    return field;
  }
  const CoarseDirections dirs = coarse_directions(geometry, points, normals, weights, direction_passes, false);
  VectorGrid field{geometry, {}};
  for (auto& c : field.components) assign_large(c, geometry.num_nodes());
  const Eigen::Vector3i d = geometry.dims;
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < d.z(); ++k) {
    for (int j = 0; j < d.y(); ++j) {
      for (int i = 0; i < d.x(); ++i) {
        const std::int64_t n = geometry.index(i, j, k);
        const Eigen::Vector3d f = dirs.field_at(geometry.position(i, j, k), density[n]);
        for (int a = 0; a < 3; ++a) field.components[a][n] = f[a];
      }
    }
  }
  return field;
}

void normalize_field(VectorGrid& field, const std::vector<Eigen::Vector3f>& points, int filter_passes) {
  const GridGeometry& g = field.geometry;
  const auto node_field = [&](int i, int j, int k) {
    const std::int64_t n = g.index(i, j, k);
    return Eigen::Vector3d(field.components[0][n], field.components[1][n], field.components[2][n]);
  };
  const double scale = normalization_scale(g, mean_norm_at_samples(g, points, node_field), filter_passes);
  if (scale == 1.0) return;
  for (auto& c : field.components) {
    const std::int64_t n = static_cast<std::int64_t>(c.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) c[i] *= scale;
  }
}

namespace {

// Planes [0, planes) in `blocks` runs of consecutive planes, shared among
// the threads of the enclosing parallel region, each thread with its own
// window of F: a run fills the planes around its first one, then per plane
// k fills k + 1 and takes the divergence of k (the two planes around a run
// are evaluated twice; a few runs per thread balance the planes that cut
// more of the surface).
template <typename Fill, typename Divergence>
void for_each_plane_in_blocks(int planes, int blocks, Fill&& fill, Divergence&& divergence) {
#pragma omp for schedule(dynamic, 1)
  for (int b = 0; b < blocks; ++b) {
    const int k_begin = static_cast<int>(std::int64_t{planes} * b / blocks);
    const int k_end = static_cast<int>(std::int64_t{planes} * (b + 1) / blocks);
    if (k_begin > 0) fill(k_begin - 1);
    fill(k_begin);
    for (int k = k_begin; k < k_end; ++k) {
      if (k + 1 < planes) fill(k + 1);
      divergence(k);
    }
  }
}

// How many blocks of planes the threads share in for_each_plane_in_blocks
// (one without threads, never more than the planes).
int plane_blocks(std::int64_t nodes, int num_planes) {
  int blocks = 1;
#ifdef _OPENMP
  if (worth_threads(nodes)) blocks = 4 * omp_get_max_threads();
#endif
  return std::max(1, std::min(blocks, num_planes));
}

}  // namespace

ScalarGrid divergence(const VectorGrid& field) {
  const GridGeometry& g = field.geometry;
  ScalarGrid div(g);
  const double inv2h = 1.0 / (2.0 * g.spacing);
  const Eigen::Vector3i d = g.dims;
  const std::int64_t plane = std::int64_t{d.x()} * d.y();
  const auto& c = field.components;
#pragma omp parallel for schedule(static)
  for (int k = 0; k < d.z(); ++k) {
    const std::int64_t at = k * plane;
    divergence_plane(d, inv2h, c[0].data() + at, c[1].data() + at, k > 0 ? c[2].data() + at - plane : nullptr,
                     k < d.z() - 1 ? c[2].data() + at + plane : nullptr, div.values.data() + at);
  }
  return div;
}

ScalarGrid density_scaled_rhs(const GridGeometry& geometry,
                              const std::vector<Eigen::Vector3f>& points,
                              const std::vector<Eigen::Vector3f>& normals,
                              const std::vector<float>& weights,
                              const FieldPasses& passes) {
  if (passes.direction % 4 != 0 || !geometry.can_coarsen(3)) {
    VectorGrid field = density_scaled_field(geometry, points, normals, weights, passes.density, passes.direction);
    normalize_field(field, points, passes.filter);
    ScalarGrid rhs = divergence(field);
    for (double& v : rhs.values) v = -v;
    return rhs;
  }
  // The result first: where freed memory is kept for reuse (hos-recon), the
  // temporaries above it then leave one free block at the heap's top for the
  // solver's arrays instead of a hole below the result.
  ScalarGrid rhs(geometry);
  // Single precision: the density only scales F, and it is one of the two
  // grid-sized arrays that set hos-recon's peak memory.
  std::vector<float> density = splat_weights<float>(geometry, ActiveNodes::all(geometry), points, weights);
  box_filter(geometry, density, passes.density);
  const CoarseDirections dirs = coarse_directions(geometry, points, normals, weights, passes.direction, false);
  const auto node_field = [&](int i, int j, int k) {
    return dirs.field_at(geometry.position(i, j, k), density[geometry.index(i, j, k)]);
  };
  const double scale = normalization_scale(geometry, mean_norm_at_samples(geometry, points, node_field), passes.filter);

  // -div of the scaled F, the scale and the sign folded into the difference
  // factor (divergence is linear).
  const double factor = -scale / (2.0 * geometry.spacing);
  const Eigen::Vector3i d = geometry.dims;
  const std::int64_t plane = std::int64_t{d.x()} * d.y();
  // Per thread a window of F in planes k - 1, k, k + 1 (see
  // for_each_plane_in_blocks).
  const int blocks = plane_blocks(geometry.num_nodes(), d.z());
#pragma omp parallel
  {
    // window[k mod 3][a]: component a of F in plane k.
    std::array<std::array<std::vector<double>, 3>, 3> window;
    for (auto& slot : window) {
      for (auto& c : slot) c.resize(plane);
    }
    const auto slot = [&](int k) -> std::array<std::vector<double>, 3>& { return window[k % 3]; };
    const auto fill = [&](int k) {
      auto& w = slot(k);
      for (int j = 0; j < d.y(); ++j) {
        for (int i = 0; i < d.x(); ++i) {
          const Eigen::Vector3d f = node_field(i, j, k);
          const std::int64_t q = std::int64_t{j} * d.x() + i;
          for (int a = 0; a < 3; ++a) w[a][q] = f[a];
        }
      }
    };
    for_each_plane_in_blocks(d.z(), blocks, fill, [&](int k) {
      divergence_plane(d, factor, slot(k)[0].data(), slot(k)[1].data(), k > 0 ? slot(k - 1)[2].data() : nullptr,
                       k + 1 < d.z() ? slot(k + 1)[2].data() : nullptr, rhs.values.data() + k * plane);
    });
  }
  return rhs;
}

namespace {

// The stored spans of a band grouped by plane: the spans of plane k are
// [plane_span[k], plane_span[k + 1]), their storage contiguous from first(k).
struct StoredPlanes {
  StoredPlanes(const ActiveNodes& nodes, int num_planes)
      : spans(nodes.stored_spans()), plane_span(num_planes + 1, spans.size()), storage_size(nodes.storage_size()) {
    for (std::size_t s = spans.size(); s-- > 0;) plane_span[spans[s].k] = s;
    for (int k = num_planes - 1; k >= 0; --k) plane_span[k] = std::min(plane_span[k], plane_span[k + 1]);
  }
  std::int64_t first(int k) const { return plane_span[k] < spans.size() ? spans[plane_span[k]].first : storage_size; }
  // The most nodes any plane stores.
  std::int64_t largest() const {
    std::int64_t n = 0;
    for (int k = 0; k + 1 < static_cast<int>(plane_span.size()); ++k) n = std::max(n, first(k + 1) - first(k));
    return n;
  }

  std::vector<NodeSpan> spans;
  std::vector<std::size_t> plane_span;
  std::int64_t storage_size;
};

}  // namespace

StoredField density_scaled_rhs_near_samples(const GridGeometry& geometry,
                                            const std::vector<Eigen::Vector3f>& points,
                                            const std::vector<Eigen::Vector3f>& normals,
                                            const std::vector<float>& weights,
                                            const FieldPasses& passes) {
  // The filtered density reaches passes.density nodes beyond the samples'
  // cell corners, F as far, -div F one node more.
  StoredField rhs;
  rhs.nodes = std::make_shared<const ActiveNodes>(band_around_samples(geometry, points, passes.density + 1));
  const ActiveNodes& nodes = *rhs.nodes;
  std::vector<float> density = splat_weights<float>(geometry, nodes, points, weights);
  box_filter_stored(geometry, nodes, density, passes.density);
  const CoarseDirections dirs = coarse_directions(geometry, points, normals, weights, passes.direction, true);
  const auto node_field = [&](int i, int j, int k) {
    return dirs.field_at(geometry.position(i, j, k), stored_value(nodes, density, i, j, k));
  };
  const double scale = normalization_scale(geometry, mean_norm_at_samples(geometry, points, node_field), passes.filter);

  // -div of the scaled F as in density_scaled_rhs, F (zero where the
  // density is) evaluated plane by plane: three planes of it at a time
  // instead of three band-sized arrays (bunny at grid 1024: 800 MB).
  const Eigen::Vector3i d = geometry.dims;
  const StoredPlanes planes(nodes, d.z());
  const std::vector<NodeSpan>& spans = planes.spans;
  const std::vector<std::size_t>& plane_span = planes.plane_span;
  const auto plane_first = [&](int k) { return planes.first(k); };
  const std::int64_t largest_plane = planes.largest();
  const double factor = -scale / (2.0 * geometry.spacing);
  assign_large(rhs.values, static_cast<std::size_t>(nodes.storage_size()));
  const int blocks = plane_blocks(nodes.storage_size(), d.z());
#pragma omp parallel
  {
    // window[k mod 3][a]: component a of F in plane k, from plane_first(k) on.
    std::array<std::array<std::vector<double>, 3>, 3> window;
    for (auto& slot : window) {
      for (auto& c : slot) c.resize(static_cast<std::size_t>(largest_plane));
    }
    const auto slot = [&](int k) -> std::array<std::vector<double>, 3>& { return window[k % 3]; };
    const auto fill = [&](int k) {
      auto& w = slot(k);
      const std::int64_t first = plane_first(k);
      for (std::size_t s = plane_span[k]; s < plane_span[k + 1]; ++s) {
        const NodeSpan& sp = spans[s];
        for (int i = sp.begin; i < sp.end; ++i) {
          const std::int64_t n = sp.first + (i - sp.begin);
          const Eigen::Vector3d v = dirs.field_at(geometry.position(i, sp.j, sp.k), density[n]);
          for (int a = 0; a < 3; ++a) w[a][n - first] = v[a];
        }
      }
    };
    // Rows of F_y below and above, of F_z below and above.
    std::array<std::vector<double>, 4> rows;
    for (auto& row : rows) row.resize(d.x());
    const auto divergence_of_plane = [&](int k) {
      for (std::size_t s = plane_span[k]; s < plane_span[k + 1]; ++s) {
        const NodeSpan& sp = spans[s];
        const int len = sp.end - sp.begin;
        nodes.gather_row(slot(k)[1].data(), sp.j - 1, sp.k, sp.begin, sp.end, rows[0].data(), plane_first(k));
        nodes.gather_row(slot(k)[1].data(), sp.j + 1, sp.k, sp.begin, sp.end, rows[1].data(), plane_first(k));
        if (k > 0) {
          nodes.gather_row(slot(k - 1)[2].data(), sp.j, k - 1, sp.begin, sp.end, rows[2].data(), plane_first(k - 1));
        }
        if (k + 1 < d.z()) {
          nodes.gather_row(slot(k + 1)[2].data(), sp.j, k + 1, sp.begin, sp.end, rows[3].data(), plane_first(k + 1));
        }
        const double* fx = slot(k)[0].data() + (sp.first - plane_first(k));
        for (int t = 0; t < len; ++t) {
          // The sums and their order of divergence_plane; a stored run ends
          // where F is zero, so the x neighbours beyond it add zero.
          double v = 0.0;
          v += ((t + 1 < len ? fx[t + 1] : 0.0) - (t > 0 ? fx[t - 1] : 0.0)) * factor;
          v += (rows[1][t] - rows[0][t]) * factor;
          v += ((k + 1 < d.z() ? rows[3][t] : 0.0) - (k > 0 ? rows[2][t] : 0.0)) * factor;
          rhs.values[sp.first + t] = v;
        }
      }
    };
    for_each_plane_in_blocks(d.z(), blocks, fill, divergence_of_plane);
  }
  return rhs;
}

}  // namespace hos::recon
