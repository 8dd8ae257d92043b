// Disjoint sets (union-find) over 0 .. n-1 with path halving. The representative of a set is its
// smallest element, so representatives (and everything numbered from them) do not depend on the
// order of the unions: the connected components of the graphs (thesis ch. 1 §3) and of meshes.
#pragma once

#include <algorithm>
#include <cstddef>
#include <numeric>
#include <vector>

namespace xsect {

class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), std::size_t(0)); }

  std::size_t size() const { return parent_.size(); }

  /// Back to n singletons (reusing the room: for many small sets in a loop).
  void reset(std::size_t n) {
    parent_.resize(n);
    std::iota(parent_.begin(), parent_.end(), std::size_t(0));
  }

  /// The smallest element of x's set.
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }

  /// Joins the sets of a and b.
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::size_t> parent_;
};

}  // namespace xsect
