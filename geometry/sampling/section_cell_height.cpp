// Upper bound of method 2's cell height h'_C by branch and bound (see section_cell_height.h).
// CGAL's kd-tree headers stay in this file.
#include "geometry/sampling/section_cell_height.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>

#include <algorithm>
#include <cmath>
#include <queue>

#include "geometry/sampling/cell_polytope.h"

namespace xsect {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Traits = CGAL::Search_traits_3<K>;
using Search = CGAL::Orthogonal_k_neighbor_search<Traits>;

struct Box {
  Vec3 centre, half;
  double radius = 0, bound = 0;
  bool operator<(const Box& o) const { return bound < o.bound; }  // the largest bound on top
};

}  // namespace

SectionHeightBound sectionHeightBound(const std::vector<Plane>& planes, const std::vector<int>& sides,
                                      const Vec3& interior, const Vec3& lo, const Vec3& hi,
                                      const std::vector<Vec3>& section_points, double target_mm,
                                      double resolution_mm, const SectionHeightParams& params) {
  SectionHeightBound out;
  if (section_points.empty() || sides.size() != planes.size() || !(resolution_mm > 0)) return out;
  const CellPolytope cell = cellPolytope(planes, sides, interior, lo, hi);
  if (cell.empty()) return out;
  const std::vector<int>& cellPlanes = cell.planes;

  std::vector<K::Point_3> pts;
  pts.reserve(section_points.size());
  for (const Vec3& p : section_points) pts.emplace_back(p.x(), p.y(), p.z());
  const Search::Tree tree(pts.begin(), pts.end());
  const auto nearest = [&](const Vec3& x) {
    const Search search(tree, K::Point_3(x.x(), x.y(), x.z()), 1);
    return std::sqrt(search.begin()->second);
  };
  // Whether a ball may meet the cell (it lies outside none of the cell's planes, nor the box).
  const auto mayMeet = [&](const Vec3& c, double r) {
    for (int k = 0; k < 3; ++k)
      if (c[k] - r > hi[k] || c[k] + r < lo[k]) return false;
    for (const int j : cellPlanes)
      if (-double(sides[std::size_t(j)]) * planes[std::size_t(j)].signedDistance(c) > r) return false;
    return true;
  };

  const Vec3 bmin = cell.lo, bmax = cell.hi;
  std::priority_queue<Box> queue;
  const auto push = [&](const Vec3& c, const Vec3& half) {
    const double r = half.norm();
    if (!mayMeet(c, r)) return;
    queue.push({c, half, r, nearest(c) + r});
  };
  push(0.5 * (bmin + bmax), 0.5 * (bmax - bmin));
  if (queue.empty()) return out;
  for (;;) {
    const Box top = queue.top();
    const bool fine = top.radius <= std::max(resolution_mm, params.relative_resolution * top.bound);
    if (top.bound < target_mm || fine || out.boxes >= params.max_boxes || queue.size() > 200000) {
      out.upper_mm = top.bound;
      out.farthest = top.centre;
      return out;
    }
    queue.pop();
    ++out.boxes;
    const Vec3 h = 0.5 * top.half;
    for (int i = 0; i < 8; ++i) {
      const Vec3 c = top.centre + Vec3((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
      push(c, h);
    }
    if (queue.empty()) {  // every child fell outside by rounding: the parent's bound stands
      out.upper_mm = top.bound;
      out.farthest = top.centre;
      return out;
    }
  }
}

}  // namespace xsect
