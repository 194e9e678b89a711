#include "recon/energy_operator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "recon/grid_transfer.h"

namespace hos::recon {
namespace {

// row[i] += sum_t c[t] * src[i + ox[t]] for begin <= i < end, one pass for
// all taps. nx < 0: every i + ox[t] is inside the row; otherwise taps beyond
// [0, nx) read ghost nodes (zero) and are skipped.
template <typename T>
void add_taps(int count, const int* ox, const T* c, const T* src, int begin, int end, int nx, T* __restrict row) {
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

EnergyOperator::EnergyOperator(const GridGeometry& geometry,
                               SmoothnessEnergy energy,
                               double hessian_weight,
                               std::vector<double> tv_node_weights,
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

template <typename T>
void EnergyOperator::add_total_variation(const NodeSpan& span, std::int64_t start, const T* x, T* row) const {
  // -div(w grad x) with edge weights (w_i + w_j) / 2; ghosts are zero. The
  // weights are per grid node: TV operators cover the whole grid, whose
  // storage index is the node index.
  const Eigen::Vector3i d = geometry_.dims;
  const double tv_scale = tv_weight_ / (geometry_.spacing * geometry_.spacing);
  const std::int64_t strides[3] = {1, d.x(), std::int64_t{d.x()} * d.y()};
  for (int i = span.begin; i < span.end; ++i) {
    const Eigen::Vector3i p(i, span.j, span.k);
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

template <bool kWithL1, typename T, typename SpanFn>
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
  const ActiveNodes& active = *active_;
  const std::vector<NodeSpan>& spans = active.spans();
  const std::int64_t num_spans = static_cast<std::int64_t>(spans.size());
#pragma omp parallel if (worth_threads(active.count()))
  {
    std::vector<T> row_buffer(nx), l1_buffer(kWithL1 ? nx : 0);
    std::optional<CellProducts<T>> cell_products;
    if (screening_->kept_per_cell()) cell_products.emplace(*screening_, active, x);
#pragma omp for schedule(static)
    for (std::int64_t s = 0; s < num_spans; ++s) {
      const NodeSpan& span = spans[s];
      const int j = span.j, k = span.k, b = span.begin, e = span.end;
      // x of a neighbour row within +-2 (or null outside the grid), indexed
      // by i; each looked up once for the stencil and the screening term.
      std::array<const T*, 25> x_rows_near;
      std::uint32_t looked_up = 0;
      const auto x_row = [&](int dy, int dz) -> const T* {
        const int q = (dy + 2) + 5 * (dz + 2);
        if (!(looked_up >> q & 1)) {
          const std::int64_t base = active.row_base(j + dy, k + dz, b);
          x_rows_near[q] = base == ActiveNodes::kNotStored ? nullptr : x + base;
          looked_up |= std::uint32_t{1} << q;
        }
        return x_rows_near[q];
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
      if (tv) add_total_variation(span, start, x, row);
      if (!screening_->empty()) {
        std::array<const T*, 9> x_rows;
        for (int q = 0; q < 9; ++q) x_rows[q] = x_row(q % 3 - 1, q / 3 - 1);
        if (cell_products) cell_products->reach_plane(k);
        screening_->add_row(std::int64_t{k} * d.y() + j, b, e, x_rows, cell_products ? cell_products->data() : nullptr,
                            row);
      }
      if constexpr (kWithL1) {
        l1_row(span, l1_buffer.data());
        span_fn(start, b, e, static_cast<const T*>(row), static_cast<const T*>(l1_buffer.data()));
      } else {
        span_fn(start, b, e, static_cast<const T*>(row));
      }
    }
  }
}

template <typename T>
void EnergyOperator::l1_row(const NodeSpan& span, T* l1_row) const {
  if (tv_node_weights_.empty()) {
    std::fill(l1_row + span.begin, l1_row + span.end, static_cast<T>(stencil_abs_sum_));
  } else {
    const std::int64_t start = span.first - span.begin;  // node i at start + i
    for (int i = span.begin; i < span.end; ++i) l1_row[i] = static_cast<T>(l1_diagonal(start + i));
  }
  screening_->add_row_sums(std::int64_t{span.k} * geometry_.dims.y() + span.j, span.begin, span.end, 1.0, l1_row);
}

void EnergyOperator::apply(const std::vector<double>& x, std::vector<double>& y) const {
  if (y.size() != x.size()) assign_large(y, x.size());
  apply(x.data(), y.data());
}

template <typename T>
void EnergyOperator::apply(const T* x, T* y) const {
  for_each_span(x, [&](std::int64_t start, int b, int e, const T* ax) { std::copy(ax + b, ax + e, y + start + b); });
}

template <typename T>
void EnergyOperator::residual(const T* b, const T* x, T* r) const {
  for_each_span(x, [&](std::int64_t start, int i0, int i1, const T* ax) {
    for (int i = i0; i < i1; ++i) r[start + i] = b[start + i] - ax[i];
  });
}

template <typename T>
void EnergyOperator::jacobi(const T* b, const T* x, T* out) const {
  for_each_span<true>(x, [&](std::int64_t start, int i0, int i1, const T* ax, const T* l1) {
    for (int i = i0; i < i1; ++i) {
      const std::int64_t n = start + i;
      out[n] = x[n] + (b[n] - ax[i]) / l1[i];
    }
  });
}

template <typename T>
void EnergyOperator::smoothing_step(const T* b, const T* x, double keep, double a, T* step) const {
  const T k = static_cast<T>(keep), s = static_cast<T>(a);
  for_each_span<true>(x, [&](std::int64_t start, int i0, int i1, const T* ax, const T* l1) {
    for (int i = i0; i < i1; ++i) {
      const std::int64_t n = start + i;
      step[n] = (keep == 0.0 ? T(0) : k * step[n]) + s * (b[n] - ax[i]) / l1[i];
    }
  });
}

template <typename T>
void EnergyOperator::scale_by_inverse_l1(const T* in, double a, T* out, T* copy) const {
  const T s = static_cast<T>(a);
  for_each_active_span(*active_, [&](const NodeSpan& span) {
    // The span's row sums first, in out itself.
    const std::int64_t start = span.first - span.begin;
    T* row = out + start;
    l1_row(span, row);
    for (int i = span.begin; i < span.end; ++i) row[i] = s * in[start + i] / row[i];
    if (copy) std::copy(row + span.begin, row + span.end, copy + start + span.begin);
  });
}

template void EnergyOperator::apply<float>(const float*, float*) const;
template void EnergyOperator::apply<double>(const double*, double*) const;
template void EnergyOperator::residual<float>(const float*, const float*, float*) const;
template void EnergyOperator::residual<double>(const double*, const double*, double*) const;
template void EnergyOperator::jacobi<float>(const float*, const float*, float*) const;
template void EnergyOperator::jacobi<double>(const double*, const double*, double*) const;
template void EnergyOperator::smoothing_step<float>(const float*, const float*, double, double, float*) const;
template void EnergyOperator::smoothing_step<double>(const double*, const double*, double, double, double*) const;
template void EnergyOperator::scale_by_inverse_l1<float>(const float*, double, float*, float*) const;
template void EnergyOperator::scale_by_inverse_l1<double>(const double*, double, double*, double*) const;

void EnergyOperator::scale_screening(double factor) {
  auto scaled = std::make_shared<ScreeningTerm>(*screening_);
  scaled->scale(factor);
  screening_ = std::move(scaled);
}

void EnergyOperator::set_screening(std::shared_ptr<const std::vector<Eigen::Vector3f>> points, double weight) {
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
  for_each_active_span(*active_, [&](const NodeSpan& span) { l1_row(span, l1 + (span.first - span.begin)); });
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

}  // namespace hos::recon
