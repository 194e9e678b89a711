#include "recon/active_nodes.h"

#include <algorithm>

namespace hos::recon {
namespace {

// out[t] |= in[t - d] | in[t + d] for 1 <= d <= radius over n lines of len
// bytes (line t at t * stride), lines beyond [0, n) absent: a dilation along
// the axis that steps from line to line, by whole contiguous lines so it
// vectorises.
void dilate_lines(const std::uint8_t* in, std::uint8_t* out, int n, std::int64_t stride, std::int64_t len, int radius) {
  for (int t = 0; t < n; ++t) {
    std::uint8_t* __restrict o = out + t * stride;
    for (int s = std::max(0, t - radius); s <= std::min(n - 1, t + radius); ++s) {
      if (s == t) continue;
      const std::uint8_t* __restrict src = in + s * stride;
      for (std::int64_t i = 0; i < len; ++i) o[i] |= src[i];
    }
  }
}

// mask |= mask shifted by up to +-radius along one axis: a node becomes
// active if an active node lies within radius along the axis.
void dilate_axis(const GridGeometry& g, std::vector<std::uint8_t>& mask, int axis, int radius) {
  if (radius <= 0) return;
  const Eigen::Vector3i d = g.dims;
  const std::int64_t nx = d.x(), plane = nx * d.y();
  const std::vector<std::uint8_t> in(mask);
  if (axis == 2) {
    // Planes are the lines; chunks of them go to the threads.
    const std::int64_t chunk = 4096;
#pragma omp parallel for schedule(static)
    for (std::int64_t c = 0; c < plane; c += chunk) {
      dilate_lines(in.data() + c, mask.data() + c, d.z(), plane, std::min(chunk, plane - c), radius);
    }
    return;
  }
#pragma omp parallel for schedule(static)
  for (int k = 0; k < d.z(); ++k) {
    if (axis == 1) {
      dilate_lines(in.data() + k * plane, mask.data() + k * plane, d.y(), nx, nx, radius);
      continue;
    }
    for (int j = 0; j < d.y(); ++j) {
      const std::uint8_t* __restrict src = in.data() + k * plane + j * nx;
      std::uint8_t* __restrict o = mask.data() + k * plane + j * nx;
      for (int dx = 1; dx <= radius && dx < nx; ++dx) {
        for (std::int64_t i = dx; i < nx; ++i) o[i] |= src[i - dx];
        for (std::int64_t i = 0; i + dx < nx; ++i) o[i] |= src[i + dx];
      }
    }
  }
}

// Calls fn(begin, end) for every run of nonzero bytes of a row of n.
template <typename Fn>
void for_each_run(const std::uint8_t* row, int n, Fn&& fn) {
  for (int i = 0; i < n;) {
    if (!row[i]) {
      ++i;
      continue;
    }
    const int begin = i;
    while (i < n && row[i]) ++i;
    fn(begin, i);
  }
}

}  // namespace

ActiveNodes ActiveNodes::all(const GridGeometry& g) {
  ActiveNodes a;
  a.dims_ = g.dims;
  a.spans_.reserve(static_cast<std::size_t>(g.dims.y()) * g.dims.z());
  for (int k = 0; k < g.dims.z(); ++k) {
    for (int j = 0; j < g.dims.y(); ++j) a.spans_.push_back({j, k, 0, g.dims.x(), g.index(0, j, k)});
  }
  a.count_ = g.num_nodes();
  a.storage_size_ = g.num_nodes();
  return a;
}

ActiveNodes ActiveNodes::from_mask(const GridGeometry& g, std::vector<std::uint8_t> mask) {
  ActiveNodes a;
  a.dims_ = g.dims;
  std::int64_t count = 0;
#pragma omp parallel for reduction(+ : count) schedule(static)
  for (std::int64_t n = 0; n < g.num_nodes(); ++n) count += mask[n] != 0;
  if (count == g.num_nodes()) return all(g);
  a.count_ = count;
  a.mask_ = std::move(mask);
  std::vector<std::uint8_t> stored(a.mask_);
  for (int axis = 0; axis < 3; ++axis) dilate_axis(g, stored, axis, kHalo);
  // Runs of stored nodes and of active nodes, row after row; the storage
  // follows the dense order, so sweeps keep its memory access pattern.
  const int nx = g.dims.x();
  const std::int64_t rows = std::int64_t{g.dims.y()} * g.dims.z();
  a.row_runs_.resize(rows + 1);
  std::int64_t offset = 0;
  for (std::int64_t row = 0; row < rows; ++row) {
    a.row_runs_[row] = static_cast<std::int64_t>(a.stored_.size());
    for_each_run(stored.data() + row * nx, nx, [&](int lo, int hi) {
      a.stored_.push_back({lo, hi, offset - lo});
      offset += hi - lo;
    });
    const int j = static_cast<int>(row % g.dims.y()), k = static_cast<int>(row / g.dims.y());
    for_each_run(a.mask_.data() + row * nx, nx, [&](int begin, int end) { a.spans_.push_back({j, k, begin, end, 0}); });
  }
  a.row_runs_[rows] = static_cast<std::int64_t>(a.stored_.size());
  a.storage_size_ = offset;
  for (NodeSpan& span : a.spans_) span.first = a.row_base(span.j, span.k, span.begin) + span.begin;
  return a;
}

std::vector<NodeSpan> ActiveNodes::stored_spans() const {
  if (is_all()) return spans_;
  std::vector<NodeSpan> spans;
  spans.reserve(stored_.size());
  const std::int64_t rows = static_cast<std::int64_t>(row_runs_.size()) - 1;
  for (std::int64_t row = 0; row < rows; ++row) {
    const int j = static_cast<int>(row % dims_.y()), k = static_cast<int>(row / dims_.y());
    for (std::int64_t r = row_runs_[row]; r < row_runs_[row + 1]; ++r) {
      spans.push_back({j, k, stored_[r].lo, stored_[r].hi, stored_[r].base + stored_[r].lo});
    }
  }
  return spans;
}

template <typename T>
void ActiveNodes::gather(const T* dense, T* stored) const {
  if (is_all()) {
    std::copy(dense, dense + storage_size_, stored);
    return;
  }
  const std::int64_t rows = static_cast<std::int64_t>(row_runs_.size()) - 1;
#pragma omp parallel for schedule(static)
  for (std::int64_t row = 0; row < rows; ++row) {
    for (std::int64_t r = row_runs_[row]; r < row_runs_[row + 1]; ++r) {
      const StoredRun& run = stored_[r];
      std::copy(dense + row * dims_.x() + run.lo, dense + row * dims_.x() + run.hi, stored + run.base + run.lo);
    }
  }
}

template <typename T>
void ActiveNodes::scatter_active(const T* stored, T* dense) const {
  for_each_active_span(*this, [&](const NodeSpan& span) {
    const std::int64_t row = std::int64_t{span.k} * dims_.y() + span.j;
    std::copy(stored + span.first, stored + span.first + (span.end - span.begin), dense + row * dims_.x() + span.begin);
  });
}

template void ActiveNodes::gather<double>(const double*, double*) const;
template void ActiveNodes::gather<float>(const float*, float*) const;
template void ActiveNodes::scatter_active<double>(const double*, double*) const;
template void ActiveNodes::scatter_active<float>(const float*, float*) const;

ActiveNodes ActiveNodes::coarsened(const GridGeometry& fine, const GridGeometry& coarse) const {
  if (is_all()) return all(coarse);
  // Coarse node I sits on fine node 2I + 1: it is active if an active fine
  // node lies within one node of it along every axis.
  std::vector<std::uint8_t> near(mask_);
  for (auto& v : near) v = !v;
  for (int axis = 0; axis < 3; ++axis) dilate_axis(fine, near, axis, 1);
  for (auto& v : near) v = !v;
  std::vector<std::uint8_t> mask(coarse.num_nodes());
  const Eigen::Vector3i dc = coarse.dims;
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < dc.z(); ++k) {
    for (int j = 0; j < dc.y(); ++j) {
      for (int i = 0; i < dc.x(); ++i) {
        mask[coarse.index(i, j, k)] = near[fine.index(2 * i + 1, 2 * j + 1, 2 * k + 1)];
      }
    }
  }
  return from_mask(coarse, std::move(mask));
}

ActiveNodes band_around_samples(const GridGeometry& g, const std::vector<Eigen::Vector3f>& points, int voxels) {
  std::vector<std::uint8_t> mask(g.num_nodes(), 0);
  for (const auto& p : points) {
    const TrilinearStencil s = trilinear_stencil(g, p.cast<double>());
    for (int c = 0; c < 8; ++c) {
      const int i = s.corner.x() + (c & 1), j = s.corner.y() + ((c >> 1) & 1), k = s.corner.z() + (c >> 2);
      if (g.contains(i, j, k)) mask[g.index(i, j, k)] = 1;
    }
  }
  for (int axis = 0; axis < 3; ++axis) dilate_axis(g, mask, axis, voxels);
  return ActiveNodes::from_mask(g, std::move(mask));
}

}  // namespace hos::recon
