// Upper bound of method 2's cell height h'_C by branch and bound (see section_cell_height.h).
// CGAL's convex-hull and kd-tree headers stay in this file.
#include "geometry/sampling/section_cell_height.h"

#include <CGAL/Convex_hull_3/dual/halfspace_intersection_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/Search_traits_3.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <queue>

namespace xsect {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Traits = CGAL::Search_traits_3<K>;
using Search = CGAL::Orthogonal_k_neighbor_search<Traits>;

/// The cell's vertices from the planes listed in `use` (indices into planes) and the box.
bool polytopeVertices(const std::vector<Plane>& planes, const std::vector<int>& sides, const std::vector<int>& use,
                      const Vec3& interior, const Vec3& lo, const Vec3& hi, std::vector<Vec3>* vertices) {
  // CGAL intersects the negative sides a x + b y + c z + d ≤ 0; the cell is σ (n · x − n · o) ≥ 0.
  std::vector<K::Plane_3> hs;
  hs.reserve(use.size() + 6);
  for (const int j : use) {
    const Plane& p = planes[std::size_t(j)];
    const double s = double(sides[std::size_t(j)]);
    hs.emplace_back(-s * p.normal.x(), -s * p.normal.y(), -s * p.normal.z(), s * p.normal.dot(p.origin));
  }
  for (int k = 0; k < 3; ++k) {
    Vec3 e = Vec3::Unit(k);
    hs.emplace_back(e.x(), e.y(), e.z(), -hi[k]);     // x_k ≤ hi_k
    hs.emplace_back(-e.x(), -e.y(), -e.z(), lo[k]);   // x_k ≥ lo_k
  }
  CGAL::Polyhedron_3<K> P;
  try {
    CGAL::halfspace_intersection_3(hs.begin(), hs.end(), P, K::Point_3(interior.x(), interior.y(), interior.z()));
  } catch (...) {
    return false;
  }
  vertices->clear();
  for (auto v = P.vertices_begin(); v != P.vertices_end(); ++v)
    vertices->emplace_back(v->point().x(), v->point().y(), v->point().z());
  return vertices->size() >= 4;
}

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
  // The planes by their distance to the interior point; the interior point must be strictly inside.
  std::vector<double> dist(planes.size());
  for (std::size_t j = 0; j < planes.size(); ++j) {
    dist[j] = double(sides[j]) * planes[j].signedDistance(interior);
    if (!(dist[j] > 0)) return out;
  }
  for (int k = 0; k < 3; ++k)
    if (!(interior[k] > lo[k] && interior[k] < hi[k])) return out;
  std::vector<int> order(planes.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return dist[std::size_t(a)] != dist[std::size_t(b)] ? dist[std::size_t(a)] < dist[std::size_t(b)] : a < b;
  });
  // A plane farther from the interior point than every vertex of the polytope of the nearer planes
  // cannot cut it: grow the nearer set until none is left out.
  std::size_t used = std::min<std::size_t>(order.size(), 32);
  std::vector<Vec3> vertices;
  for (;;) {
    const std::vector<int> use(order.begin(), order.begin() + std::ptrdiff_t(used));
    if (!polytopeVertices(planes, sides, use, interior, lo, hi, &vertices)) return out;
    double radius = 0;
    for (const Vec3& v : vertices) radius = std::max(radius, (v - interior).norm());
    std::size_t reach = used;
    while (reach < order.size() && dist[std::size_t(order[reach])] < radius) ++reach;
    if (reach == used) break;
    used = std::min(order.size(), std::max(reach, 2 * used));
  }
  const std::vector<int> cellPlanes(order.begin(), order.begin() + std::ptrdiff_t(used));

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

  Vec3 bmin = vertices.front(), bmax = vertices.front();
  for (const Vec3& v : vertices) bmin = bmin.cwiseMin(v), bmax = bmax.cwiseMax(v);
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
