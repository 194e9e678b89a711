#include "recon/energy_operator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <parallel/algorithm>
#include <stdexcept>

namespace hos::recon {
namespace {

using StencilMap = std::map<std::array<int, 3>, double>;

StencilMap convolve(const StencilMap& a, const StencilMap& b) {
  StencilMap out;
  for (const auto& [oa, ca] : a) {
    for (const auto& [ob, cb] : b) {
      out[{oa[0] + ob[0], oa[1] + ob[1], oa[2] + ob[2]}] += ca * cb;
    }
  }
  return out;
}

void accumulate(StencilMap& into, const StencilMap& s, double w) {
  for (const auto& [o, c] : s) into[o] += w * c;
}

// Paper eq. (9): second differences and the cross differences.
StencilMap pure_second(int axis, double h) {
  std::array<int, 3> m{0, 0, 0}, p{0, 0, 0};
  m[axis] = -1;
  p[axis] = 1;
  const double s = 1.0 / (h * h);
  return {{m, s}, {{0, 0, 0}, -2.0 * s}, {p, s}};
}

StencilMap mixed_second(int a, int b, double h) {
  const double s = 1.0 / (4.0 * h * h);
  StencilMap out;
  for (int sa : {-1, 1}) {
    for (int sb : {-1, 1}) {
      std::array<int, 3> o{0, 0, 0};
      o[a] = sa;
      o[b] = sb;
      out[o] = s * sa * sb;
    }
  }
  return out;
}

StencilMap negative_laplacian(double h) {
  StencilMap out;
  const double s = 1.0 / (h * h);
  out[{0, 0, 0}] = 6.0 * s;
  for (int a = 0; a < 3; ++a) {
    std::array<int, 3> o{0, 0, 0};
    o[a] = 1;
    out[o] = -s;
    o[a] = -1;
    out[o] = -s;
  }
  return out;
}

// row[i] += sum_t c[t] * src[i + ox[t]] for begin <= i < end, one pass for
// all taps. nx < 0: every i + ox[t] is inside the row; otherwise taps beyond
// [0, nx) read ghost nodes (zero) and are skipped.
template <typename T>
void add_taps(int count, const int* ox, const T* c, const T* src, int begin, int end, int nx,
              T* __restrict row) {
  if (nx >= 0) {
    for (int t = 0; t < count; ++t) {
      const int i0 = std::max(begin, -ox[t]), i1 = std::min(end, nx - ox[t]);
      for (int i = i0; i < i1; ++i) row[i] += c[t] * src[i + ox[t]];
    }
    return;
  }
  const T* __restrict s0 = src + ox[0];
  switch (count) {
    case 1:
      for (int i = begin; i < end; ++i) row[i] += c[0] * s0[i];
      return;
    case 3: {
      const T* __restrict s1 = src + ox[1];
      const T* __restrict s2 = src + ox[2];
      for (int i = begin; i < end; ++i) row[i] += c[0] * s0[i] + c[1] * s1[i] + c[2] * s2[i];
      return;
    }
    case 5: {
      const T* __restrict s1 = src + ox[1];
      const T* __restrict s2 = src + ox[2];
      const T* __restrict s3 = src + ox[3];
      const T* __restrict s4 = src + ox[4];
      for (int i = begin; i < end; ++i) {
        row[i] += c[0] * s0[i] + c[1] * s1[i] + c[2] * s2[i] + c[3] * s3[i] + c[4] * s4[i];
      }
      return;
    }
    default:
      for (int t = 0; t < count; ++t) {
        for (int i = begin; i < end; ++i) row[i] += c[t] * src[i + ox[t]];
      }
  }
}

}  // namespace

double Stencil::center() const {
  for (std::size_t k = 0; k < offsets.size(); ++k) {
    if (offsets[k].isZero()) return coefficients[k];
  }
  return 0.0;
}

std::vector<StencilRow> Stencil::rows() const {
  std::vector<StencilRow> rows;
  for (std::size_t t = 0; t < offsets.size(); ++t) {
    const Eigen::Vector3i& o = offsets[t];
    auto it = std::find_if(rows.begin(), rows.end(),
                           [&](const StencilRow& r) { return r.dy == o.y() && r.dz == o.z(); });
    if (it == rows.end()) {
      it = rows.insert(rows.end(), StencilRow{});
      it->dy = o.y();
      it->dz = o.z();
    }
    it->ox[it->count] = o.x();
    it->c[it->count++] = coefficients[t];
  }
  return rows;
}

double Stencil::abs_sum() const {
  double s = 0.0;
  for (double c : coefficients) s += std::abs(c);
  return s;
}

Stencil energy_stencil(SmoothnessEnergy energy, double h, double hessian_weight) {
  StencilMap total = negative_laplacian(h);
  StencilMap hessian;
  switch (energy) {
    case SmoothnessEnergy::kMembrane:
      // |grad f|^2 as smoothness: H = -Lap.
      hessian = negative_laplacian(h);
      break;
    case SmoothnessEnergy::kTotalVariation:
      break;  // per-node weights, see EnergyOperator
    case SmoothnessEnergy::kPureSecond:
    case SmoothnessEnergy::kFullHessian:
      for (int a = 0; a < 3; ++a) {
        const StencilMap d = pure_second(a, h);
        accumulate(hessian, convolve(d, d), 1.0);
      }
      if (energy == SmoothnessEnergy::kFullHessian) {
        for (int a = 0; a < 3; ++a) {
          for (int b = a + 1; b < 3; ++b) {
            const StencilMap d = mixed_second(a, b, h);
            accumulate(hessian, convolve(d, d), 2.0);
          }
        }
      }
      break;
  }
  accumulate(total, hessian, 2.0 * hessian_weight);
  Stencil s;
  for (const auto& [o, c] : total) {
    if (c == 0.0) continue;
    s.offsets.emplace_back(o[0], o[1], o[2]);
    s.coefficients.push_back(c);
  }
  return s;
}

EnergyOperator::EnergyOperator(const GridGeometry& geometry, SmoothnessEnergy energy,
                               double hessian_weight, std::vector<double> tv_node_weights,
                               double tv_weight)
    : geometry_(geometry),
      energy_(energy),
      hessian_weight_(hessian_weight),
      stencil_(energy_stencil(energy, geometry.spacing, hessian_weight)),
      tv_node_weights_(std::move(tv_node_weights)),
      tv_weight_(tv_weight) {
  stencil_abs_sum_ = stencil_.abs_sum();
  stencil_rows_ = stencil_.rows();
  active_ = std::make_shared<const ActiveNodes>(ActiveNodes::all(geometry_));
  screening_ = std::make_shared<const ScreeningTerm>();
}

void EnergyOperator::set_active(std::shared_ptr<const ActiveNodes> active) {
  if (!tv_node_weights_.empty() && !active->is_all()) {
    throw std::invalid_argument("EnergyOperator: the total-variation term covers the whole grid only");
  }
  active_ = std::move(active);
}

ScreeningTerm::ScreeningTerm(const GridGeometry& g, const std::vector<Eigen::Vector3f>& points,
                             double weight)
    : geometry_(g), weight_(weight) {
  struct Sample {
    std::int64_t cell;  // lower corner on the grid padded by two nodes: a sort key
    std::size_t input;  // index in points
    Eigen::Vector3i corner;
    Eigen::Vector3d frac;
  };
  const Eigen::Vector3i d = g.dims;
  std::vector<Sample> samples(points.size());
#pragma omp parallel for schedule(static)
  for (std::size_t s = 0; s < points.size(); ++s) {
    const TrilinearStencil st = trilinear_stencil(g, points[s].cast<double>());
    // Clamped to [-2, d]: a clamped cell has every corner outside the grid
    // along that axis, so cells that share a key touch the same nodes.
    const Eigen::Vector3i c = st.corner.cwiseMax(-2).cwiseMin(d);
    samples[s] = {(std::int64_t{c.z() + 2} * (d.y() + 3) + c.y() + 2) * (d.x() + 3) + c.x() + 2, s,
                  st.corner, st.frac};
  }
  // Sorted by cell, each corner's node index ascends with the cell: the
  // touched nodes are the merge of 8 sorted lists (one per corner) instead of
  // a sort of all corners, and every corner's compact index is found by a
  // forward walk.
  // Ties broken by the input order: the sums below, and so the result, do not
  // depend on the sort or the thread count.
  __gnu_parallel::sort(samples.begin(), samples.end(), [](const Sample& a, const Sample& b) {
    return a.cell < b.cell || (a.cell == b.cell && a.input < b.input);
  });
  std::vector<std::size_t> first_of_cell;  // samples of cell q: [first_of_cell[q], first_of_cell[q + 1])
  for (std::size_t s = 0; s < samples.size(); ++s) {
    if (s == 0 || samples[s].cell != samples[s - 1].cell) first_of_cell.push_back(s);
  }
  const std::size_t num_cells = first_of_cell.size();
  first_of_cell.push_back(samples.size());
  const auto corner_node = [&](std::size_t q, int c) -> std::int64_t {
    const Eigen::Vector3i p =
        samples[first_of_cell[q]].corner + Eigen::Vector3i(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    return g.contains(p.x(), p.y(), p.z()) ? g.index(p.x(), p.y(), p.z()) : -1;
  };
  std::vector<std::int64_t> nodes, corner_list, merged;
  for (int c = 0; c < 8; ++c) {
    corner_list.clear();
    for (std::size_t q = 0; q < num_cells; ++q) {
      const std::int64_t n = corner_node(q, c);
      if (n >= 0) corner_list.push_back(n);
    }
    merged.resize(nodes.size() + corner_list.size());
    merged.erase(std::set_union(nodes.begin(), nodes.end(), corner_list.begin(), corner_list.end(),
                                merged.begin()),
                 merged.end());
    nodes.swap(merged);
  }
  // Compact node index of every cell's 8 corners (-1 outside the grid).
  std::vector<std::array<std::int64_t, 8>> cell_nodes(num_cells);
#pragma omp parallel for schedule(static, 1)
  for (int c = 0; c < 8; ++c) {
    std::size_t walk = 0;
    for (std::size_t q = 0; q < num_cells; ++q) {
      const std::int64_t n = corner_node(q, c);
      if (n >= 0) {
        while (nodes[walk] < n) ++walk;
      }
      cell_nodes[q][c] = n >= 0 ? static_cast<std::int64_t>(walk) : -1;
    }
  }
  // Each touched node's 27 coefficients (offsets (-1..1)^3, x fastest),
  // contiguous in node order.
  // The cells of one plane of cells (one z) write node planes z and z + 1
  // only: planes of one parity run in parallel without write conflicts.
  std::vector<std::size_t> first_of_plane;  // cells of plane p: [first_of_plane[p], first_of_plane[p + 1])
  const std::int64_t cells_per_plane = std::int64_t{d.x() + 3} * (d.y() + 3);
  for (std::size_t q = 0; q < num_cells; ++q) {
    if (q == 0 || samples[first_of_cell[q]].cell / cells_per_plane !=
                      samples[first_of_cell[q - 1]].cell / cells_per_plane) {
      first_of_plane.push_back(q);
    }
  }
  const std::int64_t num_planes = static_cast<std::int64_t>(first_of_plane.size());
  first_of_plane.push_back(num_cells);
  coefficients_.assign(27 * nodes.size(), 0.0f);
  for (int parity = 0; parity < 2; ++parity) {
#pragma omp parallel for schedule(dynamic, 4)
    for (std::int64_t p = 0; p < num_planes; ++p) {
      const std::size_t first = first_of_plane[p];
      if ((samples[first_of_cell[first]].cell / cells_per_plane) % 2 != parity) continue;
      for (std::size_t q = first; q < first_of_plane[p + 1]; ++q) {
        const std::array<std::int64_t, 8>& corners = cell_nodes[q];
        for (std::size_t s = first_of_cell[q]; s < first_of_cell[q + 1]; ++s) {
          const TrilinearStencil st{samples[s].corner, samples[s].frac};
          std::array<double, 8> w;
          for (int c = 0; c < 8; ++c) w[c] = st.weight(c & 1, (c >> 1) & 1, (c >> 2) & 1);
          for (int a = 0; a < 8; ++a) {
            if (corners[a] < 0) continue;
            float* row = &coefficients_[27 * corners[a]];
            for (int b = 0; b < 8; ++b) {
              if (corners[b] < 0) continue;
              const int o = ((b & 1) - (a & 1) + 1) + 3 * (((b >> 1) & 1) - ((a >> 1) & 1) + 1) +
                            9 * (((b >> 2) & 1) - ((a >> 2) & 1) + 1);
              row[o] += static_cast<float>(weight * w[a] * w[b]);
            }
          }
        }
      }
    }
  }
  // Runs of consecutive nodes on one row.
  num_nodes_ = static_cast<std::int64_t>(nodes.size());
  for (std::size_t e = 0; e < nodes.size();) {
    std::size_t last = e + 1;
    while (last < nodes.size() && nodes[last] == nodes[last - 1] + 1 && nodes[last] % d.x() != 0) {
      ++last;
    }
    Run run;
    run.begin = static_cast<int>(nodes[e] % d.x());
    run.end = run.begin + static_cast<int>(last - e);
    run.j = static_cast<int>((nodes[e] / d.x()) % d.y());
    run.k = static_cast<int>(nodes[e] / (std::int64_t{d.x()} * d.y()));
    run.coefficients = 27 * static_cast<std::int64_t>(e);
    run.interior = run.j > 0 && run.j < d.y() - 1 && run.k > 0 && run.k < d.z() - 1 &&
                   run.begin > 0 && run.end < d.x();
    runs_.push_back(run);
    e = last;
  }
  const std::int64_t rows = std::int64_t{d.y()} * d.z();
  row_begin_.resize(rows + 1);
  std::size_t e = 0;
  for (std::int64_t r = 0; r <= rows; ++r) {
    while (e < runs_.size() && std::int64_t{runs_[e].k} * d.y() + runs_[e].j < r) ++e;
    row_begin_[r] = static_cast<std::int64_t>(e);
  }
}

std::shared_ptr<const ScreeningTerm> ScreeningTerm::coarsened(
    const std::vector<Eigen::Vector3f>& points) const {
  if (!coarser_) coarser_ = std::make_shared<const ScreeningTerm>(geometry_.coarsened(), points, weight_ / 8.0);
  return coarser_;
}

void ScreeningTerm::scale(double factor) {
  weight_ *= factor;
  coarser_.reset();
  for (float& c : coefficients_) c = static_cast<float>(c * factor);
}

double ScreeningTerm::mean_row_sum() const {
  double sum = 0.0;
  for (float c : coefficients_) sum += c;
  return num_nodes_ == 0 ? 0.0 : sum / static_cast<double>(num_nodes_);
}

template <typename T>
void ScreeningTerm::add_row_sums(std::int64_t row, int begin, int end, double scale, T* y_row) const {
  if (runs_.empty()) return;
  for (std::int64_t e = row_begin_[row]; e < row_begin_[row + 1]; ++e) {
    const Run& run = runs_[e];
    const int i0 = std::max(run.begin, begin), i1 = std::min(run.end, end);
    const float* c = coefficients_.data() + run.coefficients + 27 * (i0 - run.begin);
    for (int i = i0; i < i1; ++i, c += 27) {
      double sum = 0.0;
      for (int q = 0; q < 27; ++q) sum += c[q];
      y_row[i] += static_cast<T>(scale * sum);
    }
  }
}

void ScreeningTerm::add_target(double target, std::vector<double>& rhs) const {
  const std::int64_t nx = geometry_.dims.x();
  const std::int64_t rows = static_cast<std::int64_t>(row_begin_.size()) - 1;
  for (std::int64_t row = 0; row < rows; ++row) {
    add_row_sums(row, 0, static_cast<int>(nx), target, rhs.data() + row * nx);
  }
}

template <typename T>
void ScreeningTerm::add_row(std::int64_t row, int begin, int end, const std::array<const T*, 9>& x_rows,
                            T* y_row) const {
  const int nx = geometry_.dims.x();
  for (std::int64_t e = row_begin_[row]; e < row_begin_[row + 1]; ++e) {
    const Run& run = runs_[e];
    const int i0 = std::max(run.begin, begin), i1 = std::min(run.end, end);
    const float* c = coefficients_.data() + run.coefficients + 27 * (i0 - run.begin);
    if (run.interior) {
      // Every neighbour inside the grid: a fixed 27-term sum per node, three
      // neighbours along x from each of the 9 rows.
      const std::array<const T*, 9> r = x_rows;
      for (int i = i0; i < i1; ++i, c += 27) {
        T sum = 0;
        for (int q = 0; q < 9; ++q) {
          const T* p = r[q] + (i - 1);
          sum += static_cast<T>(c[3 * q]) * p[0] + static_cast<T>(c[3 * q + 1]) * p[1] +
                 static_cast<T>(c[3 * q + 2]) * p[2];
        }
        y_row[i] += sum;
      }
      continue;
    }
    for (int i = i0; i < i1; ++i, c += 27) {
      T sum = 0;
      for (int q = 0; q < 27; ++q) {
        const int ii = i + q % 3 - 1;
        // Neighbours outside the grid have zero coefficients: skip them.
        if (x_rows[q / 3] && ii >= 0 && ii < nx) sum += static_cast<T>(c[q]) * x_rows[q / 3][ii];
      }
      y_row[i] += sum;
    }
  }
}

template <typename T, typename SpanFn>
void EnergyOperator::for_each_span(const T* x, SpanFn&& span_fn) const {
  const GridGeometry& g = geometry_;
  const Eigen::Vector3i d = g.dims;
  const int nx = d.x();
  // The stencil's terms grouped by the row they read: each span looks up a
  // neighbour row's storage once and adds all its taps in one pass (energy
  // (4): 13 rows of 1, 3 or 5 taps instead of 25 passes).
  std::vector<std::array<T, 5>> row_coefficients(stencil_rows_.size());
  for (std::size_t r = 0; r < stencil_rows_.size(); ++r) {
    for (int q = 0; q < stencil_rows_[r].count; ++q) row_coefficients[r][q] = static_cast<T>(stencil_rows_[r].c[q]);
  }
  const bool tv = !tv_node_weights_.empty();
  const double tv_scale = tv_weight_ / (g.spacing * g.spacing);
  const std::int64_t strides[3] = {1, d.x(), std::int64_t{d.x()} * d.y()};
  const ActiveNodes& active = *active_;
  const std::vector<NodeSpan>& spans = active.spans();
  const std::int64_t num_spans = static_cast<std::int64_t>(spans.size());
#pragma omp parallel if (worth_threads(active.count()))
  {
    std::vector<T> row_buffer(nx);
#pragma omp for schedule(static)
    for (std::int64_t s = 0; s < num_spans; ++s) {
      const NodeSpan& span = spans[s];
      const int j = span.j, k = span.k, b = span.begin, e = span.end;
      // x of a neighbour row (or null outside the grid), indexed by i.
      const auto x_row = [&](int dy, int dz) -> const T* {
        const std::int64_t base = active.row_base(j + dy, k + dz, b);
        return base == ActiveNodes::kNotStored ? nullptr : x + base;
      };
      T* __restrict row = row_buffer.data();
      std::fill(row + b, row + e, T(0));
      const bool inner = b >= 2 && e <= nx - 2;  // every tap of every node inside the grid
      for (std::size_t r = 0; r < stencil_rows_.size(); ++r) {
        const StencilRow& taps = stencil_rows_[r];
        const T* src = x_row(taps.dy, taps.dz);
        if (!src) continue;
        add_taps(taps.count, taps.ox.data(), row_coefficients[r].data(), src, b, e, inner ? -1 : nx, row);
      }
      // Storage index of node i of this span: start + i.
      const std::int64_t start = span.first - b;
      if (tv) {
        // -div(w grad x) with edge weights (w_i + w_j) / 2; ghosts are zero.
        // The weights are per grid node: TV operators cover the whole grid,
        // whose storage index is the node index.
        for (int i = b; i < e; ++i) {
          const Eigen::Vector3i p(i, j, k);
          const std::int64_t idx = start + i;
          const double wi = tv_node_weights_[idx];
          double t = 0.0;
          for (int a = 0; a < 3; ++a) {
            for (int sgn : {-1, 1}) {
              const bool inside = sgn > 0 ? p[a] < d[a] - 1 : p[a] > 0;
              const std::int64_t nb = idx + sgn * strides[a];
              const double wj = inside ? tv_node_weights_[nb] : wi;
              t += 0.5 * (wi + wj) * (x[idx] - (inside ? x[nb] : T(0)));
            }
          }
          row[i] += static_cast<T>(tv_scale * t);
        }
      }
      if (!screening_->empty()) {
        std::array<const T*, 9> x_rows;
        for (int q = 0; q < 9; ++q) x_rows[q] = x_row(q % 3 - 1, q / 3 - 1);
        screening_->add_row(std::int64_t{k} * d.y() + j, b, e, x_rows, row);
      }
      span_fn(start, b, e, static_cast<const T*>(row));
    }
  }
}

void EnergyOperator::apply(const std::vector<double>& x, std::vector<double>& y) const {
  if (y.size() != x.size()) assign_large(y, x.size());
  apply(x.data(), y.data());
}

template <typename T>
void EnergyOperator::apply(const T* x, T* y) const {
  for_each_span(x, [&](std::int64_t start, int b, int e, const T* ax) {
    std::copy(ax + b, ax + e, y + start + b);
  });
}

template <typename T>
void EnergyOperator::residual(const T* b, const T* x, T* r) const {
  for_each_span(x, [&](std::int64_t start, int i0, int i1, const T* ax) {
    for (int i = i0; i < i1; ++i) r[start + i] = b[start + i] - ax[i];
  });
}

template <typename T>
void EnergyOperator::jacobi(const T* b, const T* x, const T* inv_l1, T* out) const {
  for_each_span(x, [&](std::int64_t start, int i0, int i1, const T* ax) {
    for (int i = i0; i < i1; ++i) {
      const std::int64_t n = start + i;
      out[n] = x[n] + (b[n] - ax[i]) * inv_l1[n];
    }
  });
}

template void EnergyOperator::apply<float>(const float*, float*) const;
template void EnergyOperator::apply<double>(const double*, double*) const;
template void EnergyOperator::residual<float>(const float*, const float*, float*) const;
template void EnergyOperator::residual<double>(const double*, const double*, double*) const;
template void EnergyOperator::jacobi<float>(const float*, const float*, const float*, float*) const;
template void EnergyOperator::jacobi<double>(const double*, const double*, const double*, double*) const;

void EnergyOperator::scale_screening(double factor) {
  auto scaled = std::make_shared<ScreeningTerm>(*screening_);
  scaled->scale(factor);
  screening_ = std::move(scaled);
}

void EnergyOperator::set_screening(std::shared_ptr<const std::vector<Eigen::Vector3f>> points,
                                   double weight) {
  screening_points_ = std::move(points);
  screening_ = screening_points_ && weight > 0.0
                   ? std::make_shared<const ScreeningTerm>(geometry_, *screening_points_, weight)
                   : std::make_shared<const ScreeningTerm>();
}

double EnergyOperator::l1_diagonal(std::int64_t node) const {
  if (tv_node_weights_.empty()) return stencil_abs_sum_;
  // Each TV edge contributes its weight twice to the row's absolute sum.
  const GridGeometry& g = geometry_;
  const Eigen::Vector3i d = g.dims;
  const int i = static_cast<int>(node % d.x());
  const int j = static_cast<int>((node / d.x()) % d.y());
  const int k = static_cast<int>(node / (std::int64_t{d.x()} * d.y()));
  const double wi = tv_node_weights_[node];
  double edges = 0.0;
  const int p[3] = {i, j, k};
  const std::int64_t strides[3] = {1, d.x(), std::int64_t{d.x()} * d.y()};
  for (int a = 0; a < 3; ++a) {
    edges += 0.5 * (wi + (p[a] > 0 ? tv_node_weights_[node - strides[a]] : wi));
    edges += 0.5 * (wi + (p[a] < d[a] - 1 ? tv_node_weights_[node + strides[a]] : wi));
  }
  return stencil_abs_sum_ + 2.0 * tv_weight_ / (g.spacing * g.spacing) * edges;
}

template <typename T>
void EnergyOperator::l1_diagonals(T* l1) const {
  const int ny = geometry_.dims.y();
  for_each_active_span(*active_, [&](const NodeSpan& span) {
    const std::int64_t start = span.first - span.begin;  // node i at start + i
    for (int i = span.begin; i < span.end; ++i) l1[start + i] = static_cast<T>(l1_diagonal(start + i));
    screening_->add_row_sums(std::int64_t{span.k} * ny + span.j, span.begin, span.end, 1.0, l1 + start);
  });
}

template void EnergyOperator::l1_diagonals<float>(float*) const;
template void EnergyOperator::l1_diagonals<double>(double*) const;

EnergyOperator EnergyOperator::coarsened() const {
  const GridGeometry coarse = geometry_.coarsened();
  std::vector<double> weights;
  if (!tv_node_weights_.empty()) {
    restrict_to_coarse(geometry_, tv_node_weights_, coarse, weights);
  }
  EnergyOperator op(coarse, energy_, hessian_weight_, std::move(weights), tv_weight_);
  if (!screening_->empty()) {
    op.screening_points_ = screening_points_;
    op.screening_ = screening_->coarsened(*screening_points_);
  }
  if (!active_->is_all()) {
    op.set_active(std::make_shared<const ActiveNodes>(active_->coarsened(geometry_, coarse)));
  }
  return op;
}

namespace {

// Fine node j lies at coarse coordinate (j - 1) / 2: on a coarse node when j
// is odd, halfway between two when j is even.
struct AxisWeights {
  int c0, c1;
  double w0, w1;
};
AxisWeights axis_weights(int j) {
  if (j % 2 == 1) return {(j - 1) / 2, (j - 1) / 2, 1.0, 0.0};
  return {j / 2 - 1, j / 2, 0.5, 0.5};
}

}  // namespace

template <typename T>
void restrict_to_coarse(const GridGeometry& fine, const ActiveNodes& fine_nodes, const T* r,
                        const GridGeometry& /*coarse*/, const ActiveNodes& coarse_active, T* rc) {
  const int nx = fine.dims.x();
#pragma omp parallel if (worth_threads(8 * coarse_active.count()))
  {
    // The 9 fine rows around a coarse row, fine nodes 2 begin <= i <= 2 end.
    std::vector<T> lines(9 * static_cast<std::size_t>(nx + 1));
#pragma omp for schedule(static)
    for (std::int64_t s = 0; s < static_cast<std::int64_t>(coarse_active.spans().size()); ++s) {
      const NodeSpan& span = coarse_active.spans()[s];
      const int lo = 2 * span.begin, hi = 2 * span.end + 1;
      for (int q = 0; q < 9; ++q) {
        fine_nodes.gather_row(r, 2 * span.j + q % 3, 2 * span.k + q / 3, lo, hi,
                              lines.data() + q * std::size_t(nx + 1));
      }
      for (int i = span.begin; i < span.end; ++i) {
        // Coarse node (i, j, k) sits on fine node (2i+1, 2j+1, 2k+1); its 27
        // fine neighbours are inside the fine grid by construction.
        double sum = 0.0;
        for (int q = 0; q < 9; ++q) {
          const T* p = lines.data() + q * std::size_t(nx + 1) + (2 * i + 1 - lo);
          const double w = (q % 3 == 1 ? 1.0 : 0.5) * (q / 3 == 1 ? 1.0 : 0.5);
          sum += w * (0.5 * p[-1] + p[0] + 0.5 * p[1]);
        }
        rc[span.first + (i - span.begin)] = static_cast<T>(sum / 8.0);
      }
    }
  }
}

namespace {

// prolongate_add on the fine nodes of these spans.
template <typename T>
void prolongate_add_spans(const GridGeometry& coarse, const ActiveNodes& coarse_nodes, const T* ec,
                          const std::vector<NodeSpan>& spans, std::int64_t count, T* x) {
  const Eigen::Vector3i dc = coarse.dims;
#pragma omp parallel if (worth_threads(count))
  {
    // The coarse values interpolated in y and z for one fine row, padded by a
    // zero each side (the ghost nodes), and one coarse row.
    std::vector<double> line(dc.x() + 2);
    std::vector<T> coarse_row(dc.x());
#pragma omp for schedule(static)
    for (std::int64_t s = 0; s < static_cast<std::int64_t>(spans.size()); ++s) {
      const NodeSpan& span = spans[s];
      const AxisWeights wz = axis_weights(span.k), wy = axis_weights(span.j);
      // Fine i odd sits on coarse (i - 1) / 2, even i halfway between i/2 - 1
      // and i/2: the span reads coarse columns c0 <= i < c1.
      const int c0 = std::max(0, span.begin / 2 - 1), c1 = std::min(dc.x(), span.end / 2 + 1);
      std::fill(line.begin() + c0, line.begin() + c1 + 2, 0.0);
      for (int cz = 0; cz < 2; ++cz) {
        const double az = cz ? wz.w1 : wz.w0;
        const int kc = cz ? wz.c1 : wz.c0;
        if (az == 0.0 || kc < 0 || kc >= dc.z()) continue;
        for (int cy = 0; cy < 2; ++cy) {
          const double ay = cy ? wy.w1 : wy.w0;
          const int jc = cy ? wy.c1 : wy.c0;
          if (ay == 0.0 || jc < 0 || jc >= dc.y()) continue;
          coarse_nodes.gather_row(ec, jc, kc, c0, c1, coarse_row.data());
          for (int i = c0; i < c1; ++i) line[i + 1] += az * ay * coarse_row[i - c0];
        }
      }
      T* dst = x + (span.first - span.begin);  // dst[i]: node i of the span
      for (int i = span.begin; i < span.end; ++i) {
        dst[i] += static_cast<T>(i % 2 == 1 ? line[(i - 1) / 2 + 1] : 0.5 * (line[i / 2] + line[i / 2 + 1]));
      }
    }
  }
}

}  // namespace

template <typename T>
void prolongate_add(const GridGeometry& coarse, const ActiveNodes& coarse_nodes, const T* ec,
                    const GridGeometry& /*fine*/, const ActiveNodes& fine_active, T* x) {
  prolongate_add_spans(coarse, coarse_nodes, ec, fine_active.spans(), fine_active.count(), x);
}

void prolongate_add_to_stored(const GridGeometry& coarse, const std::vector<double>& ec,
                              const ActiveNodes& fine_nodes, double* x) {
  prolongate_add_spans(coarse, ActiveNodes::all(coarse), ec.data(), fine_nodes.stored_spans(),
                       fine_nodes.storage_size(), x);
}

template void restrict_to_coarse<float>(const GridGeometry&, const ActiveNodes&, const float*,
                                       const GridGeometry&, const ActiveNodes&, float*);
template void restrict_to_coarse<double>(const GridGeometry&, const ActiveNodes&, const double*,
                                        const GridGeometry&, const ActiveNodes&, double*);
template void prolongate_add<float>(const GridGeometry&, const ActiveNodes&, const float*,
                                    const GridGeometry&, const ActiveNodes&, float*);
template void prolongate_add<double>(const GridGeometry&, const ActiveNodes&, const double*,
                                     const GridGeometry&, const ActiveNodes&, double*);

void restrict_to_coarse(const GridGeometry& fine, const std::vector<double>& r,
                        const GridGeometry& coarse, std::vector<double>& rc) {
  assign_large(rc, coarse.num_nodes());
  restrict_to_coarse(fine, ActiveNodes::all(fine), r.data(), coarse, ActiveNodes::all(coarse), rc.data());
}

void prolongate_add(const GridGeometry& coarse, const std::vector<double>& ec,
                    const GridGeometry& fine, std::vector<double>& x) {
  prolongate_add(coarse, ActiveNodes::all(coarse), ec.data(), fine, ActiveNodes::all(fine), x.data());
}

}  // namespace hos::recon
