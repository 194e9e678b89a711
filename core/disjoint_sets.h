// Disjoint sets of the integers 0 .. n-1 (union-find with path halving):
// the pieces a mesh's faces or corners fall into.
#pragma once

#include <cstddef>
#include <numeric>
#include <vector>

namespace hos {

class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), std::size_t{0}); }

  // The representative of x's set.
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }

  void unite(std::size_t a, std::size_t b) { parent_[find(a)] = find(b); }

 private:
  std::vector<std::size_t> parent_;
};

}  // namespace hos
