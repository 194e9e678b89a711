// The regular grid the implicit function lives on (paper sec. 4).
//
// Nodes are indexed (i, j, k), 0 <= i < dims.x() etc., x fastest. Node (i, j, k)
// sits at origin + h * (i, j, k). The function is zero on a ring of "ghost"
// nodes just outside (index -1 and dims): the Dirichlet condition that makes
// the energies well posed (see docs/recon.md). A grid of dims n coarsens to
// (n - 1) / 2 with coarse node I at fine node 2I + 1, so dims are 2^L m - 1.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <vector>

#include "core/huge_pages.h"

namespace hos::recon {

struct GridGeometry {
  Eigen::Vector3i dims = Eigen::Vector3i::Zero();
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double spacing = 1.0;  // h, the same along every axis (cubic cells)

  std::int64_t num_nodes() const { return std::int64_t{dims.x()} * dims.y() * dims.z(); }
  std::int64_t index(int i, int j, int k) const { return (std::int64_t{k} * dims.y() + j) * dims.x() + i; }
  bool contains(int i, int j, int k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < dims.x() && j < dims.y() && k < dims.z();
  }
  Eigen::Vector3d position(int i, int j, int k) const { return origin + spacing * Eigen::Vector3d(i, j, k); }
  // Continuous grid coordinates of a world point.
  Eigen::Vector3d to_grid(const Eigen::Vector3d& x) const { return (x - origin) / spacing; }
  // The next coarser grid (dims (n - 1) / 2, spacing 2h).
  GridGeometry coarsened() const;
  // True if every axis can be coarsened once more and stay >= min_nodes.
  bool can_coarsen(int min_nodes) const;
};

// Smallest admissible node count >= n for a grid that coarsens levels - 1 times.
int admissible_dims(int n, int levels);

// v = n copies of value, with the storage of a large v backed by transparent
// huge pages where the system allows: first-touch page faults of the grid-sized
// arrays cost more than the arithmetic on them otherwise.
void assign_large(std::vector<double>& v, std::size_t n, double value = 0.0);
void assign_large(std::vector<float>& v, std::size_t n, float value = 0.0f);

// n zeros from calloc, for work arrays of which a banded solve touches only
// the band: the system maps a page on its first use, so the pages outside the
// band cost nothing (std::vector would write every one of them). Large ones
// ask for huge pages like assign_large (without them the stencil sweeps'
// TLB misses cost more than the pages saved).
template <typename T>
class ZeroedArray {
 public:
  ZeroedArray() = default;
  explicit ZeroedArray(std::size_t n) : values_(static_cast<T*>(std::calloc(n == 0 ? 1 : n, sizeof(T)))), size_(n) {
    if (!values_) throw std::bad_alloc();
    advise_huge_pages(values_.get(), n * sizeof(T));
  }
  std::size_t size() const { return size_; }
  T* data() const { return values_.get(); }
  T& operator[](std::size_t i) const { return values_[i]; }
  void swap(ZeroedArray& other) noexcept {
    values_.swap(other.values_);
    std::swap(size_, other.size_);
  }

 private:
  struct Free {
    void operator()(T* p) const { std::free(p); }
  };
  std::unique_ptr<T[], Free> values_;
  std::size_t size_ = 0;
};

// True if a loop over this many nodes is worth splitting across threads: on
// the small coarse levels a thread barrier costs more than the work (and much
// more when other processes share the cores).
inline bool worth_threads(std::int64_t nodes) { return nodes >= (std::int64_t{1} << 17); }

// Trilinear interpolation of per-node values at a world point (ghost nodes are zero).
double sample_trilinear(const GridGeometry& g, const std::vector<double>& values, const Eigen::Vector3d& x);

// A scalar field on the grid nodes.
struct ScalarGrid {
  GridGeometry geometry;
  std::vector<double> values;

  explicit ScalarGrid(const GridGeometry& g = {}) : geometry(g) { assign_large(values, g.num_nodes()); }
  double at(int i, int j, int k) const { return geometry.contains(i, j, k) ? values[geometry.index(i, j, k)] : 0.0; }
  // Trilinear interpolation at a world point (ghost nodes are zero).
  double sample(const Eigen::Vector3d& x) const { return sample_trilinear(geometry, values, x); }
};

// Trilinear weights of a world point: the cell's lower corner and the
// fractional position dx, dy, dz inside it (paper sec. 4.1).
struct TrilinearStencil {
  Eigen::Vector3i corner;
  Eigen::Vector3d frac;
  double weight(int ox, int oy, int oz) const {
    return (ox ? frac.x() : 1.0 - frac.x()) * (oy ? frac.y() : 1.0 - frac.y()) * (oz ? frac.z() : 1.0 - frac.z());
  }
};
TrilinearStencil trilinear_stencil(const GridGeometry& g, const Eigen::Vector3d& x);

// Calls fn(i, j, k, weight) for the corners of the cell holding x that lie
// inside the grid, z slowest, with their trilinear weights (ghost nodes are
// zero, so the others add nothing).
template <typename Fn>
void for_each_trilinear_corner(const GridGeometry& g, const Eigen::Vector3d& x, Fn&& fn) {
  const TrilinearStencil s = trilinear_stencil(g, x);
  for (int oz = 0; oz < 2; ++oz) {
    for (int oy = 0; oy < 2; ++oy) {
      for (int ox = 0; ox < 2; ++ox) {
        const int i = s.corner.x() + ox, j = s.corner.y() + oy, k = s.corner.z() + oz;
        if (g.contains(i, j, k)) fn(i, j, k, s.weight(ox, oy, oz));
      }
    }
  }
}

}  // namespace hos::recon
