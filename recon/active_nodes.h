// The nodes a solve works on: every node of the grid, or a narrow band around
// the samples. Far from every sample the implicit function only has to be
// smooth (no level set is kept there after trimming), so the finest level of a
// banded solve updates just the band, with the nodes outside held at the
// solution of the grid twice as coarse (see reconstruct.cpp).
//
// A band also defines where values are stored: the active nodes and a halo of
// kHalo nodes around them (the stencils' reach), packed row after row, so the
// solver's arrays are the size of the band instead of the grid. On this kind
// of machine, first-touch page faults of grid-sized arrays cost more than the
// arithmetic of a banded solve. For the whole grid the storage is the usual
// dense index (i + nx (j + ny k)). The active nodes are kept as runs along x
// (spans), so the stencil sweeps stay contiguous and vectorised.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "recon/grid.h"
#include "recon/row_runs.h"

namespace hos::recon {

// Active nodes (i, j, k) with begin <= i < end on one grid row; node i of the
// span is stored at first + (i - begin).
struct NodeSpan {
  int j = 0, k = 0;
  int begin = 0, end = 0;
  std::int64_t first = 0;
};

class ActiveNodes {
 public:
  // Nodes stored around the active ones along every axis: the reach of the
  // energy stencils (+-2) and of the screening term and transfers (+-1).
  static constexpr int kHalo = 2;
  static constexpr std::int64_t kNotStored = std::numeric_limits<std::int64_t>::min();

  ActiveNodes() = default;
  // Every node of the grid, stored densely.
  static ActiveNodes all(const GridGeometry& g);
  // The nodes of a set, stored with their halo.
  static ActiveNodes from_runs(const GridGeometry& g, RowRuns active);

  bool is_all() const { return all_; }
  std::int64_t count() const { return count_; }
  const std::vector<NodeSpan>& spans() const { return spans_; }
  // Values per array in this layout.
  std::int64_t storage_size() const { return storage_size_; }
  // Every stored node (active or halo) as spans in the same layout.
  std::vector<NodeSpan> stored_spans() const;
  // Is the node (dense grid index) active?
  bool contains(std::int64_t node) const {
    if (is_all()) return true;
    const std::int64_t nx = dims_.x(), row = node / nx;
    return active_.contains(static_cast<int>(node % nx), static_cast<int>(row % dims_.y()),
                            static_cast<int>(row / dims_.y()));
  }
  // A base b such that node i' of row (j, k) is stored at b + i' for every i'
  // of the stored run holding node (i, j, k); kNotStored if that node is not
  // stored (or outside the grid). For an active span's node i and rows within
  // kHalo, the run covers i' in [begin - kHalo, end + kHalo) inside the grid.
  std::int64_t row_base(int j, int k, int i) const;
  // The stored run of row (j, k) that holds node i: nodes lo <= i' < hi,
  // node i' at base + i'; empty (lo = hi) if node i is not stored.
  struct StoredWindow {
    int lo = 0, hi = 0;
    std::int64_t base = 0;
  };
  StoredWindow stored_window(int j, int k, int i) const;
  // out[t] = the value of node (lo + t, j, k), zero where it is not stored;
  // values holds the layout's values from storage index `first` on (a window
  // of the array, e.g. one plane).
  template <typename T>
  void gather_row(const T* values, int j, int k, int lo, int hi, T* out, std::int64_t first = 0) const;
  // stored = the dense grid array's values at every stored node.
  template <typename T>
  void gather(const T* dense, T* stored) const;
  // stored = the values of another layout of the same grid at every stored
  // node (zero where that layout stores none).
  template <typename T>
  void gather_from(const ActiveNodes& source, const T* values, T* stored) const;
  // The active nodes as a set (banded layouts only).
  const RowRuns& active_set() const { return active_; }
  // The stored nodes (active and halo) as a set.
  RowRuns stored_set() const;
  // Calls fn(lo, hi, base) for the stored runs of grid row j + ny k: nodes
  // lo <= i < hi, node i at base + i.
  template <typename Fn>
  void for_each_stored_run(std::int64_t row, Fn&& fn) const {
    if (is_all()) {
      fn(0, dims_.x(), row * dims_.x());
      return;
    }
    for (std::int64_t r = row_runs_[row]; r < row_runs_[row + 1]; ++r)
      fn(stored_[r].lo, stored_[r].hi, stored_[r].base);
  }
  // dense = the stored values at the active nodes (other nodes unchanged).
  template <typename T>
  void scatter_active(const T* stored, T* dense) const;
  // The coarse nodes whose 27 fine neighbours (fine nodes 2I + 1 + {-1, 0, 1}^3)
  // are all active: a coarse level whose transfers stay inside the band.
  ActiveNodes coarsened(const GridGeometry& fine, const GridGeometry& coarse) const;

 private:
  // Stored nodes lo <= i < hi of one row, node i at base + i.
  struct StoredRun {
    int lo, hi;
    std::int64_t base;
  };
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  bool all_ = false;
  RowRuns active_;  // banded: the active nodes
  std::vector<NodeSpan> spans_;
  std::vector<StoredRun> stored_;       // banded: stored runs, row after row
  std::vector<std::int64_t> row_runs_;  // banded: per row j + ny k, its first stored run
  std::int64_t count_ = 0;
  std::int64_t storage_size_ = 0;
};

// Values on the stored nodes of a layout.
struct StoredField {
  std::shared_ptr<const ActiveNodes> nodes;
  std::vector<double> values;
};

// Trilinear interpolation of f on grid g at a world point; nodes that are not
// stored (and ghost nodes) count as zero.
double sample_trilinear(const GridGeometry& g, const StoredField& f, const Eigen::Vector3d& x);

// The nodes within `voxels` nodes (per axis) of the corners of every cell that
// holds a sample.
ActiveNodes band_around_samples(const GridGeometry& g, const std::vector<Eigen::Vector3f>& points, int voxels);

// Calls fn(span) for every span of active, in parallel when the set is large.
template <typename Fn>
void for_each_active_span(const ActiveNodes& active, Fn&& fn) {
  const std::vector<NodeSpan>& spans = active.spans();
  const std::int64_t n = static_cast<std::int64_t>(spans.size());
#pragma omp parallel for schedule(static) if (worth_threads(active.count()))
  for (std::int64_t s = 0; s < n; ++s) fn(spans[s]);
}

// Calls fn(first stored index, one past the last) for every span of active.
template <typename Fn>
void for_each_active_range(const ActiveNodes& active, Fn&& fn) {
  for_each_active_span(active, [&](const NodeSpan& sp) { fn(sp.first, sp.first + (sp.end - sp.begin)); });
}

inline std::int64_t ActiveNodes::row_base(int j, int k, int i) const {
  if (j < 0 || k < 0 || j >= dims_.y() || k >= dims_.z() || i < 0 || i >= dims_.x()) return kNotStored;
  const std::int64_t row = std::int64_t{k} * dims_.y() + j;
  if (is_all()) return row * dims_.x();
  for (std::int64_t r = row_runs_[row]; r < row_runs_[row + 1]; ++r) {
    if (i < stored_[r].lo) break;
    if (i < stored_[r].hi) return stored_[r].base;
  }
  return kNotStored;
}

inline ActiveNodes::StoredWindow ActiveNodes::stored_window(int j, int k, int i) const {
  if (j < 0 || k < 0 || j >= dims_.y() || k >= dims_.z() || i < 0 || i >= dims_.x()) return {};
  const std::int64_t row = std::int64_t{k} * dims_.y() + j;
  if (is_all()) return {0, dims_.x(), row * dims_.x()};
  for (std::int64_t r = row_runs_[row]; r < row_runs_[row + 1]; ++r) {
    if (i < stored_[r].lo) break;
    if (i < stored_[r].hi) return {stored_[r].lo, stored_[r].hi, stored_[r].base};
  }
  return {};
}

template <typename T>
void ActiveNodes::gather_row(const T* values, int j, int k, int lo, int hi, T* out, std::int64_t first) const {
  std::fill(out, out + (hi - lo), T(0));
  if (j < 0 || k < 0 || j >= dims_.y() || k >= dims_.z()) return;
  const std::int64_t row = std::int64_t{k} * dims_.y() + j;
  const auto copy = [&](int a, int b, std::int64_t base) {
    a = std::max(a, lo);
    b = std::min(b, hi);
    if (a < b) std::copy(values + (base - first + a), values + (base - first + b), out + (a - lo));
  };
  if (is_all()) {
    copy(0, dims_.x(), row * dims_.x());
    return;
  }
  for (std::int64_t r = row_runs_[row]; r < row_runs_[row + 1]; ++r) {
    copy(stored_[r].lo, stored_[r].hi, stored_[r].base);
  }
}

}  // namespace hos::recon
