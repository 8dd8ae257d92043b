// A cell as a convex polytope (see cell_polytope.h). CGAL's convex-hull headers stay in this file.
#include "geometry/sampling/cell_polytope.h"

#include <CGAL/Convex_hull_3/dual/halfspace_intersection_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polyhedron_3.h>

#include <algorithm>
#include <numeric>

namespace xsect {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

/// The vertices of the intersection of the cell's side of the planes listed and the box.
bool vertices(const std::vector<Plane>& planes, const std::vector<int>& sides, const std::vector<int>& use,
              const Vec3& interior, const Vec3& lo, const Vec3& hi, std::vector<Vec3>* out) {
  // CGAL intersects the negative sides a x + b y + c z + d ≤ 0; the cell is σ (n · x − n · o) ≥ 0.
  std::vector<K::Plane_3> hs;
  hs.reserve(use.size() + 6);
  for (const int j : use) {
    const Plane& p = planes[std::size_t(j)];
    const double s = double(sides[std::size_t(j)]);
    hs.emplace_back(-s * p.normal.x(), -s * p.normal.y(), -s * p.normal.z(), s * p.normal.dot(p.origin));
  }
  for (int k = 0; k < 3; ++k) {
    const Vec3 e = Vec3::Unit(k);
    hs.emplace_back(e.x(), e.y(), e.z(), -hi[k]);    // x_k ≤ hi_k
    hs.emplace_back(-e.x(), -e.y(), -e.z(), lo[k]);  // x_k ≥ lo_k
  }
  CGAL::Polyhedron_3<K> P;
  try {
    CGAL::halfspace_intersection_3(hs.begin(), hs.end(), P, K::Point_3(interior.x(), interior.y(), interior.z()));
  } catch (...) {
    return false;
  }
  out->clear();
  for (auto v = P.vertices_begin(); v != P.vertices_end(); ++v)
    out->emplace_back(v->point().x(), v->point().y(), v->point().z());
  return out->size() >= 4;
}

}  // namespace

CellPolytope cellPolytope(const std::vector<Plane>& planes, const std::vector<int>& sides, const Vec3& interior,
                          const Vec3& lo, const Vec3& hi) {
  CellPolytope out;
  if (sides.size() != planes.size()) return out;
  for (int k = 0; k < 3; ++k)
    if (!(interior[k] > lo[k] && interior[k] < hi[k])) return out;
  std::vector<double> dist(planes.size());
  for (std::size_t j = 0; j < planes.size(); ++j) {
    dist[j] = double(sides[j]) * planes[j].signedDistance(interior);
    if (!(dist[j] > 0)) return out;
  }
  std::vector<int> order(planes.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return dist[std::size_t(a)] != dist[std::size_t(b)] ? dist[std::size_t(a)] < dist[std::size_t(b)] : a < b;
  });
  std::size_t used = std::min<std::size_t>(order.size(), 32);
  std::vector<Vec3> vs;
  for (;;) {
    const std::vector<int> use(order.begin(), order.begin() + std::ptrdiff_t(used));
    if (!vertices(planes, sides, use, interior, lo, hi, &vs)) return out;
    double radius = 0;
    for (const Vec3& v : vs) radius = std::max(radius, (v - interior).norm());
    std::size_t reach = used;
    while (reach < order.size() && dist[std::size_t(order[reach])] < radius) ++reach;
    if (reach == used) break;
    used = std::min(order.size(), std::max(reach, 2 * used));
  }
  out.vertices = std::move(vs);
  // The facets' planes: those a vertex lies on (within the rounding of the vertices, which CGAL
  // constructs in doubles: relative to the coordinates' magnitude and the cell's size).
  double scale = 0;
  for (const Vec3& v : out.vertices) scale = std::max({scale, (v - interior).norm(), v.cwiseAbs().maxCoeff()});
  const double eps = 1e-7 * std::max(scale, 1e-300);
  for (std::size_t u = 0; u < used; ++u) {
    const int j = order[u];
    for (const Vec3& v : out.vertices)
      if (double(sides[std::size_t(j)]) * planes[std::size_t(j)].signedDistance(v) <= eps) {
        out.planes.push_back(j);
        break;
      }
  }
  out.lo = out.hi = out.vertices.front();
  for (const Vec3& v : out.vertices) out.lo = out.lo.cwiseMin(v), out.hi = out.hi.cwiseMax(v);
  return out;
}

}  // namespace xsect
