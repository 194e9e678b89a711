#include "recon/row_runs.h"

#include <algorithm>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace hos::recon {
namespace {

// Builds a set row by row: row_fn(row, out) appends the row's runs to out
// (ascending, disjoint, not touching). Rows are split into chunks that the
// threads fill independently, then joined in order.
template <typename RowFn>
RowRuns build_rows(const Eigen::Vector3i& dims, RowFn&& row_fn) {
  RowRuns set;
  set.dims = dims;
  const std::int64_t rows = set.rows();
  set.row_begin.assign(rows + 1, 0);
  int chunks = 1;
#ifdef _OPENMP
  chunks = 8 * omp_get_max_threads();
#endif
  chunks = static_cast<int>(std::max<std::int64_t>(1, std::min<std::int64_t>(chunks, rows)));
  std::vector<std::vector<NodeRun>> parts(chunks);
#pragma omp parallel for schedule(dynamic, 1)
  for (int c = 0; c < chunks; ++c) {
    const std::int64_t lo = rows * c / chunks, hi = rows * (c + 1) / chunks;
    for (std::int64_t row = lo; row < hi; ++row) {
      const std::size_t before = parts[c].size();
      row_fn(row, parts[c]);
      set.row_begin[row + 1] = static_cast<std::int64_t>(parts[c].size() - before);
    }
  }
  for (std::int64_t row = 0; row < rows; ++row) set.row_begin[row + 1] += set.row_begin[row];
  set.runs.reserve(set.row_begin[rows]);
  for (auto& part : parts) set.runs.insert(set.runs.end(), part.begin(), part.end());
  return set;
}

// Appends the union of runs (any order, may overlap or touch) to out, merged.
// Runs already in out belong to earlier rows and stay apart.
void append_union(std::vector<NodeRun>& runs, std::vector<NodeRun>& out) {
  std::sort(runs.begin(), runs.end(), [](const NodeRun& a, const NodeRun& b) { return a.begin < b.begin; });
  const std::size_t first = out.size();
  for (const NodeRun& r : runs) {
    if (r.begin >= r.end) continue;
    if (out.size() > first && r.begin <= out.back().end) {
      out.back().end = std::max(out.back().end, r.end);
    } else {
      out.push_back(r);
    }
  }
}

// The runs of one row of a set.
struct RowView {
  const NodeRun* first = nullptr;
  const NodeRun* last = nullptr;
};
RowView row_of(const RowRuns& set, std::int64_t row) {
  return {set.runs.data() + set.row_begin[row], set.runs.data() + set.row_begin[row + 1]};
}

// a intersected with b (both ascending and disjoint).
std::vector<NodeRun> intersection(const std::vector<NodeRun>& a, RowView b) {
  std::vector<NodeRun> out;
  std::size_t i = 0;
  const NodeRun* q = b.first;
  while (i < a.size() && q != b.last) {
    const int lo = std::max(a[i].begin, q->begin), hi = std::min(a[i].end, q->end);
    if (lo < hi) out.push_back({lo, hi});
    if (a[i].end < q->end) {
      ++i;
    } else {
      ++q;
    }
  }
  return out;
}

// The row (j, k) of a grid with dims d, or -1 outside.
std::int64_t row_index(const Eigen::Vector3i& d, int j, int k) {
  if (j < 0 || k < 0 || j >= d.y() || k >= d.z()) return -1;
  return std::int64_t{k} * d.y() + j;
}

}  // namespace

std::int64_t RowRuns::count() const {
  std::int64_t n = 0;
  for (const NodeRun& r : runs) n += r.end - r.begin;
  return n;
}

bool RowRuns::contains(int i, int j, int k) const {
  const std::int64_t row = row_index(dims, j, k);
  if (row < 0) return false;
  for (std::int64_t r = row_begin[row]; r < row_begin[row + 1]; ++r) {
    if (i < runs[r].begin) return false;
    if (i < runs[r].end) return true;
  }
  return false;
}

RowRuns sample_cell_corners(const GridGeometry& g, const std::vector<Eigen::Vector3f>& points) {
  // Each sample adds the run [i, i + 2) of its cell's corners to the four
  // rows (j, k) .. (j + 1, k + 1): bucketed by row (a counting sort), then
  // merged row by row.
  const Eigen::Vector3i d = g.dims;
  const std::int64_t rows = std::int64_t{d.y()} * d.z();
  std::vector<std::int64_t> bucket_begin(rows + 1, 0);
  const auto for_each_row_run = [&](auto&& fn) {
    for (const auto& p : points) {
      const Eigen::Vector3i c = trilinear_stencil(g, p.cast<double>()).corner;
      const NodeRun run{std::max(c.x(), 0), std::min(c.x() + 2, d.x())};
      if (run.begin >= run.end) continue;
      for (int q = 0; q < 4; ++q) {
        const std::int64_t row = row_index(d, c.y() + (q & 1), c.z() + (q >> 1));
        if (row >= 0) fn(row, run);
      }
    }
  };
  for_each_row_run([&](std::int64_t row, const NodeRun&) { ++bucket_begin[row + 1]; });
  for (std::int64_t row = 0; row < rows; ++row) bucket_begin[row + 1] += bucket_begin[row];
  std::vector<NodeRun> buckets(bucket_begin[rows]);
  std::vector<std::int64_t> fill(bucket_begin.begin(), bucket_begin.end() - 1);
  for_each_row_run([&](std::int64_t row, const NodeRun& run) { buckets[fill[row]++] = run; });
  return build_rows(d, [&](std::int64_t row, std::vector<NodeRun>& out) {
    if (bucket_begin[row] == bucket_begin[row + 1]) return;
    std::vector<NodeRun> runs(buckets.begin() + bucket_begin[row], buckets.begin() + bucket_begin[row + 1]);
    append_union(runs, out);
  });
}

RowRuns dilated(const RowRuns& set, int radius) {
  if (radius <= 0) return set;
  const Eigen::Vector3i d = set.dims;
  // Along x within each row, then the union of the rows within radius along
  // y, then along z (a box dilation is separable).
  const RowRuns along_x = build_rows(d, [&](std::int64_t row, std::vector<NodeRun>& out) {
    std::vector<NodeRun> grown;
    for (RowView v = row_of(set, row); v.first != v.last; ++v.first) {
      grown.push_back({std::max(0, v.first->begin - radius), std::min(d.x(), v.first->end + radius)});
    }
    append_union(grown, out);
  });
  const auto along = [&](const RowRuns& in, int axis) {
    return build_rows(d, [&](std::int64_t row, std::vector<NodeRun>& out) {
      const int j = static_cast<int>(row % d.y()), k = static_cast<int>(row / d.y());
      std::vector<NodeRun> all;
      for (int s = -radius; s <= radius; ++s) {
        const std::int64_t r = axis == 1 ? row_index(d, j + s, k) : row_index(d, j, k + s);
        if (r < 0) continue;
        for (RowView v = row_of(in, r); v.first != v.last; ++v.first) all.push_back(*v.first);
      }
      append_union(all, out);
    });
  };
  return along(along(along_x, 1), 2);
}

RowRuns eroded_once(const RowRuns& set) {
  const Eigen::Vector3i d = set.dims;
  return build_rows(d, [&](std::int64_t row, std::vector<NodeRun>& out) {
    const int j = static_cast<int>(row % d.y()), k = static_cast<int>(row / d.y());
    // Along x: a run loses its end nodes unless they are at the grid's border.
    std::vector<NodeRun> kept;
    for (RowView v = row_of(set, row); v.first != v.last; ++v.first) {
      const NodeRun r{v.first->begin == 0 ? 0 : v.first->begin + 1, v.first->end == d.x() ? d.x() : v.first->end - 1};
      if (r.begin < r.end) kept.push_back(r);
    }
    // Along y and z: every in-grid row of the 3x3 neighbourhood must hold
    // the node (a box erosion is the intersection of the shifted sets).
    for (int dk = -1; dk <= 1 && !kept.empty(); ++dk) {
      for (int dj = -1; dj <= 1 && !kept.empty(); ++dj) {
        const std::int64_t r = row_index(d, j + dj, k + dk);
        if (r < 0 || r == row) continue;
        std::vector<NodeRun> shrunk;
        for (RowView v = row_of(set, r); v.first != v.last; ++v.first) {
          const NodeRun s{v.first->begin == 0 ? 0 : v.first->begin + 1,
                          v.first->end == d.x() ? d.x() : v.first->end - 1};
          if (s.begin < s.end) shrunk.push_back(s);
        }
        kept = intersection(kept, {shrunk.data(), shrunk.data() + shrunk.size()});
      }
    }
    out.insert(out.end(), kept.begin(), kept.end());
  });
}

RowRuns coarse_nodes_on(const RowRuns& fine_set, const Eigen::Vector3i& coarse_dims) {
  return build_rows(coarse_dims, [&](std::int64_t row, std::vector<NodeRun>& out) {
    const int jc = static_cast<int>(row % coarse_dims.y()), kc = static_cast<int>(row / coarse_dims.y());
    const std::int64_t fine_row = row_index(fine_set.dims, 2 * jc + 1, 2 * kc + 1);
    if (fine_row < 0) return;
    const std::size_t first = out.size();
    for (RowView v = row_of(fine_set, fine_row); v.first != v.last; ++v.first) {
      // Coarse i with begin <= 2i + 1 < end.
      const NodeRun r{v.first->begin / 2, std::min(coarse_dims.x(), v.first->end / 2)};
      if (r.begin >= r.end) continue;
      // Fine runs apart by one even node map to touching coarse runs: merged.
      if (out.size() > first && out.back().end == r.begin) {
        out.back().end = r.end;
      } else {
        out.push_back(r);
      }
    }
  });
}

}  // namespace hos::recon
