// The nodes a solve works on: every node of the grid, or a narrow band around
// the samples. Far from every sample the implicit function only has to be
// smooth (no level set is kept there after trimming), so the finest level of a
// banded solve updates just the band, with the nodes outside held at the
// solution of the grid twice as coarse (see reconstruct.cpp). The band is
// stored as runs of consecutive active nodes along x, so the stencil sweeps
// stay contiguous and vectorised.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "recon/grid.h"

namespace hos::recon {

// Active nodes (i, j, k) with begin <= i < end on one grid row.
struct NodeSpan {
  int j = 0, k = 0;
  int begin = 0, end = 0;
};

class ActiveNodes {
 public:
  ActiveNodes() = default;
  // Every node of the grid.
  static ActiveNodes all(const GridGeometry& g);
  // The nodes with mask[node] != 0 (one byte per node).
  static ActiveNodes from_mask(const GridGeometry& g, std::vector<std::uint8_t> mask);

  bool is_all() const { return mask_.empty(); }
  std::int64_t count() const { return count_; }
  const std::vector<NodeSpan>& spans() const { return spans_; }
  bool contains(std::int64_t node) const { return mask_.empty() || mask_[node] != 0; }
  // The coarse nodes whose prolongation stencil (fine nodes 2I + 1 + {-1, 0, 1}^3)
  // touches an active fine node: the support of the restricted residual.
  ActiveNodes coarsened(const GridGeometry& fine, const GridGeometry& coarse) const;

 private:
  std::vector<std::uint8_t> mask_;  // empty: every node
  std::vector<NodeSpan> spans_;
  std::int64_t count_ = 0;
};

// The nodes within `voxels` nodes (per axis) of the corners of every cell that
// holds a sample.
ActiveNodes band_around_samples(const GridGeometry& g, const std::vector<Eigen::Vector3f>& points,
                                int voxels);

// Calls fn(first node, one past the last node) for every span of active, in
// parallel when the set is large.
template <typename Fn>
void for_each_active_range(const GridGeometry& g, const ActiveNodes& active, Fn&& fn) {
  const std::vector<NodeSpan>& spans = active.spans();
  const std::int64_t n = static_cast<std::int64_t>(spans.size());
#pragma omp parallel for schedule(static) if (worth_threads(active.count()))
  for (std::int64_t s = 0; s < n; ++s) {
    const NodeSpan& sp = spans[s];
    const std::int64_t first = g.index(sp.begin, sp.j, sp.k);
    fn(first, first + (sp.end - sp.begin));
  }
}

}  // namespace hos::recon
