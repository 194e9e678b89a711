#include "recon/active_nodes.h"

#include <algorithm>

namespace hos::recon {

ActiveNodes ActiveNodes::all(const GridGeometry& g) {
  ActiveNodes a;
  a.all_ = true;
  a.dims_ = g.dims;
  a.spans_.reserve(static_cast<std::size_t>(g.dims.y()) * g.dims.z());
  for (int k = 0; k < g.dims.z(); ++k) {
    for (int j = 0; j < g.dims.y(); ++j) a.spans_.push_back({j, k, 0, g.dims.x(), g.index(0, j, k)});
  }
  a.count_ = g.num_nodes();
  a.storage_size_ = g.num_nodes();
  return a;
}

ActiveNodes ActiveNodes::from_runs(const GridGeometry& g, RowRuns active) {
  const std::int64_t count = active.count();
  if (count == g.num_nodes()) return all(g);
  ActiveNodes a;
  a.dims_ = g.dims;
  a.count_ = count;
  a.active_ = std::move(active);
  // Stored runs and active spans, row after row; the storage follows the
  // dense order, so sweeps keep its memory access pattern.
  const RowRuns stored = dilated(a.active_, kHalo);
  const std::int64_t rows = stored.rows();
  a.row_runs_ = stored.row_begin;
  a.stored_.reserve(stored.runs.size());
  std::int64_t offset = 0;
  for (const NodeRun& run : stored.runs) {
    a.stored_.push_back({run.begin, run.end, offset - run.begin});
    offset += run.end - run.begin;
  }
  a.storage_size_ = offset;
  a.spans_.reserve(a.active_.runs.size());
  for (std::int64_t row = 0; row < rows; ++row) {
    const int j = static_cast<int>(row % g.dims.y()), k = static_cast<int>(row / g.dims.y());
    for (std::int64_t r = a.active_.row_begin[row]; r < a.active_.row_begin[row + 1]; ++r) {
      const NodeRun& run = a.active_.runs[r];
      a.spans_.push_back({j, k, run.begin, run.end, a.row_base(j, k, run.begin) + run.begin});
    }
  }
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
void ActiveNodes::gather_from(const ActiveNodes& source, const T* values, T* stored) const {
  if (source.is_all()) {
    gather(values, stored);
    return;
  }
  const std::vector<NodeSpan> spans = stored_spans();
#pragma omp parallel for schedule(static)
  for (std::int64_t s = 0; s < static_cast<std::int64_t>(spans.size()); ++s) {
    const NodeSpan& sp = spans[s];
    source.gather_row(values, sp.j, sp.k, sp.begin, sp.end, stored + sp.first);
  }
}

RowRuns ActiveNodes::stored_set() const {
  RowRuns set;
  set.dims = dims_;
  if (is_all()) {
    const std::int64_t rows = set.rows();
    set.row_begin.resize(rows + 1);
    for (std::int64_t row = 0; row <= rows; ++row) set.row_begin[row] = row;
    set.runs.assign(rows, NodeRun{0, dims_.x()});
    return set;
  }
  set.row_begin = row_runs_;
  set.runs.reserve(stored_.size());
  for (const StoredRun& run : stored_) set.runs.push_back({run.lo, run.hi});
  return set;
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
template void ActiveNodes::gather_from<double>(const ActiveNodes&, const double*, double*) const;
template void ActiveNodes::gather_from<float>(const ActiveNodes&, const float*, float*) const;
template void ActiveNodes::scatter_active<double>(const double*, double*) const;
template void ActiveNodes::scatter_active<float>(const float*, float*) const;

ActiveNodes ActiveNodes::coarsened(const GridGeometry& /*fine*/, const GridGeometry& coarse) const {
  if (is_all()) return all(coarse);
  // Coarse node I sits on fine node 2I + 1: it is active if every fine node
  // within one node of it along every axis is active.
  return from_runs(coarse, coarse_nodes_on(eroded_once(active_), coarse.dims));
}

ActiveNodes band_around_samples(const GridGeometry& g, const std::vector<Eigen::Vector3f>& points, int voxels) {
  return ActiveNodes::from_runs(g, dilated(sample_cell_corners(g, points), voxels));
}

double sample_trilinear(const GridGeometry& g, const StoredField& f, const Eigen::Vector3d& x) {
  if (f.nodes->is_all()) return sample_trilinear(g, f.values, x);
  double v = 0.0;
  for_each_trilinear_corner(g, x, [&](int i, int j, int k, double w) {
    const std::int64_t base = f.nodes->row_base(j, k, i);
    if (base != ActiveNodes::kNotStored) v += w * f.values[base + i];
  });
  return v;
}

}  // namespace hos::recon
