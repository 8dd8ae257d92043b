// Points within a distance of a query point, through a hash grid: the one home of "which points
// may lie within `radius` of this one" (method 3 merges its section-vertices that coincide up to
// rounding, section_vertices.h, and welds its boundary's vertices, boundary_repairs.h). The grid's
// cells are 16 · radius wide: a query looks up its own cell and, along each axis, the neighbour
// whose boundary lies within `radius` (about 1.4 lookups on average; 8 lookups a query, with cells
// 2 · radius wide, cost multiaxial-3x40's method 3 0.2 s). The caller tests the distance with the
// positions it holds; a point is found from where it was added (one that moved after, by less
// than `radius`, may be missed by a query nearer its new position: sectionVertices moves a merged
// point by about 1e-12 mm against a radius of 1e-7 of the sample spacing).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

class NearPoints {
 public:
  /// @param radius    mm, > 0: the distance the candidates cover.
  /// @param expected  how many points will be added (room reserved).
  explicit NearPoints(double radius, std::size_t expected = 0) : radius_(radius), cell_(16 * radius) {
    head_.reserve(expected);
    next_.reserve(expected);
  }

  /// Adds point `id` (>= 0; ids need not be dense) at x.
  void add(int id, const Vec3& x) {
    if (std::size_t(id) >= next_.size()) next_.resize(std::size_t(id) + 1, -1);
    const auto [it, fresh] = head_.try_emplace(keyOf(x), id);
    if (!fresh) {
      next_[std::size_t(id)] = it->second;
      it->second = id;
    }
  }

  /// Calls visit(id) for every added point that may lie within radius of x (every one that does,
  /// and others), each once, in an order fixed by the adds.
  template <class Visit>
  void forEachCandidate(const Vec3& x, Visit&& visit) const {
    const Key own = keyOf(x);
    std::array<std::int64_t, 3> other{0, 0, 0};  // per axis: the neighbour within radius (or 0)
    for (int a = 0; a < 3; ++a) {
      const double offset = x[a] - double(own[std::size_t(a)]) * cell_;  // in [0, cell_) up to rounding
      other[std::size_t(a)] = offset < radius_ ? -1 : offset > cell_ - radius_ ? 1 : 0;
    }
    for (int k = 0; k < 8; ++k) {
      Key key = own;
      bool skip = false;
      for (int a = 0; a < 3 && !skip; ++a)
        if (k >> a & 1) {
          skip = other[std::size_t(a)] == 0;
          key[std::size_t(a)] += other[std::size_t(a)];
        }
      if (skip) continue;
      const auto it = head_.find(key);
      if (it == head_.end()) continue;
      for (int id = it->second; id >= 0; id = next_[std::size_t(id)]) visit(id);
    }
  }

 private:
  using Key = std::array<std::int64_t, 3>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 0;
      for (const std::int64_t d : k) h = (h ^ std::uint64_t(d)) * 0x100000001b3ull + 0x9e3779b97f4a7c15ull;
      return std::size_t(h ^ (h >> 29));
    }
  };
  Key keyOf(const Vec3& x) const {
    return Key{std::int64_t(std::floor(x.x() / cell_)), std::int64_t(std::floor(x.y() / cell_)),
               std::int64_t(std::floor(x.z() / cell_))};
  }

  double radius_, cell_;
  std::unordered_map<Key, int, KeyHash> head_;  ///< cell -> the last point added in it
  std::vector<int> next_;                       ///< per point id: the point added before it in its cell
};

}  // namespace xsect
