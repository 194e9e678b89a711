#include "recon/screening_term.h"

#include <limits>
#include <parallel/algorithm>
#include <stdexcept>
#include <string>

namespace hos::recon {

// The samples sorted by cell, ties broken by the input order (the sums below,
// and so the result, do not depend on the sort or the thread count). Sorted
// by cell, each corner's node index ascends with the cell: the touched nodes
// are the merge of 8 sorted lists (one per corner) instead of a sort of all
// corners, and every corner's compact index is found by a forward walk.
struct CellSamples {
  struct Sample {
    std::int64_t cell;  // lower corner on the grid padded by two nodes: a sort key
    std::size_t input;  // index in points
    Eigen::Vector3i corner;
    Eigen::Vector3d frac;
  };
  std::vector<Sample> samples;
  std::vector<std::size_t> first_of_cell;  // samples of cell q: [first_of_cell[q], first_of_cell[q + 1])

  std::size_t num_cells() const { return first_of_cell.size() - 1; }
  std::int64_t cell_key(std::size_t q) const { return samples[first_of_cell[q]].cell; }
};

namespace {

CellSamples sort_by_cell(const GridGeometry& g, const std::vector<Eigen::Vector3f>& points) {
  const Eigen::Vector3i d = g.dims;
  CellSamples out;
  std::vector<CellSamples::Sample>& samples = out.samples;
  samples.resize(points.size());
#pragma omp parallel for schedule(static)
  for (std::size_t s = 0; s < points.size(); ++s) {
    const TrilinearStencil st = trilinear_stencil(g, points[s].cast<double>());
    // Clamped to [-2, d]: a clamped cell has every corner outside the grid
    // along that axis, so cells that share a key touch the same nodes.
    const Eigen::Vector3i c = st.corner.cwiseMax(-2).cwiseMin(d);
    samples[s] = {(std::int64_t{c.z() + 2} * (d.y() + 3) + c.y() + 2) * (d.x() + 3) + c.x() + 2, s, st.corner, st.frac};
  }
  __gnu_parallel::sort(samples.begin(), samples.end(), [](const CellSamples::Sample& a, const CellSamples::Sample& b) {
    return a.cell < b.cell || (a.cell == b.cell && a.input < b.input);
  });
  for (std::size_t s = 0; s < samples.size(); ++s) {
    if (s == 0 || samples[s].cell != samples[s - 1].cell) out.first_of_cell.push_back(s);
  }
  out.first_of_cell.push_back(samples.size());
  return out;
}

// The grid node of corner c (bits x, y, z) of cell q, or -1 outside the grid.
std::int64_t corner_node(const GridGeometry& g, const CellSamples& cells, std::size_t q, int c) {
  const Eigen::Vector3i p =
      cells.samples[cells.first_of_cell[q]].corner + Eigen::Vector3i(c & 1, (c >> 1) & 1, (c >> 2) & 1);
  return g.contains(p.x(), p.y(), p.z()) ? g.index(p.x(), p.y(), p.z()) : -1;
}

// The grid nodes some cell's corner touches, ascending.
std::vector<std::int64_t> touched_nodes(const GridGeometry& g, const CellSamples& cells) {
  std::vector<std::int64_t> nodes, corner_list, merged;
  for (int c = 0; c < 8; ++c) {
    corner_list.clear();
    for (std::size_t q = 0; q < cells.num_cells(); ++q) {
      const std::int64_t n = corner_node(g, cells, q, c);
      if (n >= 0) corner_list.push_back(n);
    }
    merged.resize(nodes.size() + corner_list.size());
    merged.erase(std::set_union(nodes.begin(), nodes.end(), corner_list.begin(), corner_list.end(), merged.begin()),
                 merged.end());
    nodes.swap(merged);
  }
  return nodes;
}

// Compact node index (in nodes) of every cell's 8 corners, -1 outside the grid.
std::vector<std::array<std::int64_t, 8>> cell_corners(const GridGeometry& g,
                                                      const CellSamples& cells,
                                                      const std::vector<std::int64_t>& nodes) {
  std::vector<std::array<std::int64_t, 8>> cell_nodes(cells.num_cells());
#pragma omp parallel for schedule(static, 1)
  for (int c = 0; c < 8; ++c) {
    std::size_t walk = 0;
    for (std::size_t q = 0; q < cells.num_cells(); ++q) {
      const std::int64_t n = corner_node(g, cells, q, c);
      if (n >= 0) {
        while (nodes[walk] < n) ++walk;
      }
      cell_nodes[q][c] = n >= 0 ? static_cast<std::int64_t>(walk) : -1;
    }
  }
  return cell_nodes;
}

}  // namespace

ScreeningTerm::ScreeningTerm(const GridGeometry& g, const std::vector<Eigen::Vector3f>& points, double weight)
    : geometry_(g), weight_(weight) {
  if (points.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max() / 8)) {
    throw std::invalid_argument("ScreeningTerm: more than " +
                                std::to_string(std::numeric_limits<std::int32_t>::max() / 8) + " samples");
  }
  const CellSamples cells = sort_by_cell(g, points);
  const std::vector<std::int64_t> nodes = touched_nodes(g, cells);
  const std::vector<std::array<std::int64_t, 8>> corners = cell_corners(g, cells, nodes);
  store_cells(cells);
  index_cells_of_nodes(corners, nodes.size());
  index_runs(nodes);
  compute_row_sums();
  // The coefficients, faster to apply, unless the cells take less than half
  // their memory (bunny: 1/6 at grid 1024, 1/2.7 at 512, 1/1.3 at 256).
  const double cell_bytes = sizeof(Cell) * cells_.size() + sizeof(float) * values_.size() +
                            sizeof(std::int32_t) * (cells_of_node_.size() + first_cell_.size());
  if (27.0 * sizeof(float) * static_cast<double>(nodes.size()) <= 2.0 * cell_bytes) {
    accumulate_coefficients(corners);
    cells_ = {};
    values_ = {};
    cells_of_node_ = {};
    first_cell_ = {};
  }
}

void ScreeningTerm::store_cells(const CellSamples& cells) {
  const std::size_t num_cells = cells.num_cells();
  cells_.resize(num_cells);
  std::int64_t num_values = 0;
  for (std::size_t q = 0; q < num_cells; ++q) {
    const auto samples = static_cast<std::int32_t>(cells.first_of_cell[q + 1] - cells.first_of_cell[q]);
    cells_[q] = {cells.samples[cells.first_of_cell[q]].corner, samples, num_values, num_products_};
    num_values += samples > kMaxListedSamples ? 36 : 8 * samples;
    num_products_ += samples > kMaxListedSamples ? 8 : samples;
  }
  values_.resize(static_cast<std::size_t>(num_values));
  // Sorted by their corner clamped to [-2, dims] (sort_by_cell), a plane's
  // cells are consecutive.
  const int nz = geometry_.dims.z();
  plane_cells_.assign(static_cast<std::size_t>(nz) + 4, 0);
  for (std::size_t q = 0; q < num_cells; ++q) ++plane_cells_[std::clamp(cells_[q].corner.z(), -2, nz) + 3];
  for (std::size_t z = 1; z < plane_cells_.size(); ++z) plane_cells_[z] += plane_cells_[z - 1];
#pragma omp parallel for schedule(static)
  for (std::size_t q = 0; q < num_cells; ++q) {
    float* v = values_.data() + cells_[q].values;
    const std::size_t first = cells.first_of_cell[q], last = cells.first_of_cell[q + 1];
    if (cells_[q].samples <= kMaxListedSamples) {
      for (std::size_t s = first; s < last; ++s, v += 8) {
        const TrilinearStencil st{cells.samples[s].corner, cells.samples[s].frac};
        for (int c = 0; c < 8; ++c) v[c] = static_cast<float>(st.weight(c & 1, (c >> 1) & 1, c >> 2));
      }
      continue;
    }
    std::array<double, 36> sum{};
    for (std::size_t s = first; s < last; ++s) {
      const TrilinearStencil st{cells.samples[s].corner, cells.samples[s].frac};
      std::array<double, 8> w;
      for (int c = 0; c < 8; ++c) w[c] = st.weight(c & 1, (c >> 1) & 1, c >> 2);
      for (int a = 0; a < 8; ++a) {
        for (int b = a; b < 8; ++b) sum[moment_index(a, b)] += w[a] * w[b];
      }
    }
    for (int m = 0; m < 36; ++m) v[m] = static_cast<float>(sum[m]);
  }
}

void ScreeningTerm::index_cells_of_nodes(const std::vector<std::array<std::int64_t, 8>>& corners,
                                         std::size_t num_nodes) {
  first_cell_.assign(num_nodes + 1, 0);
  for (const auto& cell : corners) {
    for (std::int64_t n : cell) {
      if (n >= 0) ++first_cell_[n + 1];
    }
  }
  for (std::size_t n = 0; n < num_nodes; ++n) first_cell_[n + 1] += first_cell_[n];
  cells_of_node_.resize(static_cast<std::size_t>(first_cell_.back()));
  std::vector<std::int32_t> fill(first_cell_.begin(), first_cell_.end() - 1);
  for (std::size_t q = 0; q < corners.size(); ++q) {
    for (int c = 0; c < 8; ++c) {
      const std::int64_t n = corners[q][c];
      if (n >= 0) cells_of_node_[fill[n]++] = static_cast<std::int32_t>(8 * q + c);
    }
  }
}

void ScreeningTerm::compute_row_sums() {
  row_sums_.assign(first_cell_.size() - 1, 0.0f);
  for (const Run& run : runs_) {
    for (int i = run.begin; i < run.end; ++i) {
      double sum = 0.0;
      for_each_cell_of(run, i, [&](const Cell& cell, int c) { sum += cell_row_times(cell, c, kAllOnes); });
      row_sums_[run.first + (i - run.begin)] = static_cast<float>(sum);
    }
  }
}

void ScreeningTerm::accumulate_coefficients(const std::vector<std::array<std::int64_t, 8>>& corners) {
  // Per cell, entry (a, b) of its matrix goes to corner a's coefficient of
  // the offset b - a. The cells of one plane (z) write node planes z and
  // z + 1 only: planes of one parity run in parallel without write
  // conflicts. The cells are sorted by their corner clamped to [-2, d]
  // (sort_by_cell), so a plane's cells are consecutive.
  const auto plane = [&](std::size_t q) { return std::clamp(cells_[q].corner.z(), -2, geometry_.dims.z()); };
  std::vector<std::size_t> plane_first;
  for (std::size_t q = 0; q < cells_.size(); ++q) {
    if (q == 0 || plane(q) != plane(q - 1)) plane_first.push_back(q);
  }
  plane_first.push_back(cells_.size());
  coefficients_.assign(27 * row_sums_.size(), 0.0f);
  const auto num_planes = static_cast<std::int64_t>(plane_first.size()) - 1;
  for (int parity = 0; parity < 2; ++parity) {
#pragma omp parallel for schedule(dynamic, 4)
    for (std::int64_t p = 0; p < num_planes; ++p) {
      if ((plane(plane_first[p]) + 2) % 2 != parity) continue;
      for (std::size_t q = plane_first[p]; q < plane_first[p + 1]; ++q) {
        for (int a = 0; a < 8; ++a) {
          if (corners[q][a] < 0) continue;
          float* row = coefficients_.data() + 27 * corners[q][a];
          std::array<double, 8> unit{};
          for (int b = 0; b < 8; ++b) {
            // Entry (a, b): row a of the matrix times the unit vector b.
            unit.fill(0.0);
            unit[b] = 1.0;
            const int o =
                ((b & 1) - (a & 1) + 1) + 3 * (((b >> 1) & 1) - ((a >> 1) & 1) + 1) + 9 * ((b >> 2) - (a >> 2) + 1);
            row[o] += static_cast<float>(cell_row_times(cells_[q], a, unit));
          }
        }
      }
    }
  }
}

void ScreeningTerm::index_runs(const std::vector<std::int64_t>& nodes) {
  const Eigen::Vector3i d = geometry_.dims;
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
    run.first = static_cast<std::int64_t>(e);
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

std::shared_ptr<const ScreeningTerm> ScreeningTerm::coarsened(const std::vector<Eigen::Vector3f>& points) const {
  if (!coarser_) coarser_ = std::make_shared<const ScreeningTerm>(geometry_.coarsened(), points, weight_ / 8.0);
  return coarser_;
}

void ScreeningTerm::scale(double factor) {
  weight_ *= factor;
  coarser_.reset();
}

double ScreeningTerm::mean_row_sum() const {
  double sum = 0.0;
  for (float r : row_sums_) sum += r;
  return row_sums_.empty() ? 0.0 : weight_ * sum / static_cast<double>(row_sums_.size());
}

void ScreeningTerm::add_target(double target, const ActiveNodes& nodes, double* rhs) const {
  const std::int64_t rows = static_cast<std::int64_t>(row_begin_.size()) - 1;
  for (std::int64_t row = 0; row < rows; ++row) {
    if (row_begin_[row] == row_begin_[row + 1]) continue;
    nodes.for_each_stored_run(
        row, [&](int lo, int hi, std::int64_t base) { add_row_sums(row, lo, hi, target, rhs + base); });
  }
}

}  // namespace hos::recon
