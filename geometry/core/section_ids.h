// Flat ids of the sections of a list of cutting planes: section s of plane p is id first(p) + s, in
// plane order. They number the nodes of the connectivity graphs (thesis ch. 1 §3, ch. 2 §2).
#pragma once

#include <algorithm>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

class SectionIds {
 public:
  explicit SectionIds(const std::vector<CuttingPlane>& planes) : first_(planes.size() + 1, 0) {
    for (std::size_t i = 0; i < planes.size(); ++i) first_[i + 1] = first_[i] + int(planes[i].sections.size());
  }
  /// The id of section `section` of plane `plane`.
  int of(int plane, int section) const { return first_[std::size_t(plane)] + section; }
  /// The id of plane `plane`'s first section (of(plane, 0), also for a plane without sections).
  int first(int plane) const { return first_[std::size_t(plane)]; }
  /// The plane holding section `id` (0 <= id < count()); its section is id - first(planeOf(id)).
  int planeOf(int id) const {
    return int(std::upper_bound(first_.begin(), first_.end(), id) - first_.begin()) - 1;
  }
  /// How many sections all planes hold.
  int count() const { return first_.back(); }

 private:
  std::vector<int> first_;
};

}  // namespace xsect
