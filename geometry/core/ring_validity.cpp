// Repeated vertices and simplicity of a ring (see ring_validity.h). CGAL headers stay here.
#include "geometry/core/ring_validity.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>

#include <vector>

namespace xsect {

Ring withoutRepeatedVertices(const Ring& ring) {
  Ring out;
  out.reserve(ring.size());
  for (const Vec2& p : ring)
    if (out.empty() || p != out.back()) out.push_back(p);
  while (out.size() > 1 && out.back() == out.front()) out.pop_back();
  return out;
}

bool ringIsSimple(const Ring& ring) {
  if (ring.size() < 3) return false;
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<K::Point_2> pts;
  pts.reserve(ring.size());
  for (const Vec2& p : ring) pts.emplace_back(p.x(), p.y());
  return CGAL::is_simple_2(pts.begin(), pts.end(), K());
}

}  // namespace xsect
