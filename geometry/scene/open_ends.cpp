// Open ends of the data (see open_ends.h).
#include "geometry/scene/open_ends.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstdint>

namespace xsect {

namespace {

/// A plane's section vertices in world coordinates (outer rings: holes lie inside them) and their box.
struct WorldSections {
  std::vector<Vec3> vertices;
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
};

WorldSections worldSections(const CuttingPlane& p) {
  WorldSections w;
  for (const Section& s : p.sections)
    for (const Vec2& q : s.outer) {
      w.vertices.push_back(p.plane.toWorld(q));
      w.lo = w.lo.cwiseMin(w.vertices.back());
      w.hi = w.hi.cwiseMax(w.vertices.back());
    }
  return w;
}

/// The largest n·x over the box [lo, hi].
double boxSupport(const Vec3& n, const Vec3& lo, const Vec3& hi) {
  double s = 0;
  for (int a = 0; a < 3; ++a) s += n[a] * (n[a] >= 0 ? hi[a] : lo[a]);
  return s;
}

}  // namespace

std::vector<int> openEndSlices(const std::vector<CuttingPlane>& planes, double tolerance_mm) {
  std::vector<std::size_t> holding;
  for (std::size_t i = 0; i < planes.size(); ++i)
    if (!planes[i].is_virtual && !planes[i].sections.empty()) holding.push_back(i);
  std::vector<WorldSections> world(holding.size());
  tbb::parallel_for(std::size_t(0), holding.size(), [&](std::size_t k) { world[k] = worldSections(planes[holding[k]]); });
  std::vector<std::uint8_t> open(holding.size(), 0);
  tbb::parallel_for(std::size_t(0), holding.size(), [&](std::size_t k) {
    const Plane& plane = planes[holding[k]].plane;
    // Side 0: along the normal; side 1: against it. A side stays open until a vertex of another
    // plane's sections lies past the plane on it.
    std::array<bool, 2> openSide{true, true};
    for (std::size_t q = 0; q < holding.size() && (openSide[0] || openSide[1]); ++q) {
      if (q == k) continue;
      for (int side = 0; side < 2; ++side) {
        if (!openSide[side]) continue;
        const Vec3 n = side == 0 ? plane.normal : Vec3(-plane.normal);
        const double d = n.dot(plane.origin) + tolerance_mm;
        if (boxSupport(n, world[q].lo, world[q].hi) <= d) continue;  // no vertex of q can pass
        for (const Vec3& v : world[q].vertices)
          if (n.dot(v) > d) {
            openSide[side] = false;
            break;
          }
      }
    }
    open[k] = openSide[0] || openSide[1];
  });
  std::vector<int> slices;
  for (std::size_t k = 0; k < holding.size(); ++k)
    if (open[k]) slices.push_back(planes[holding[k]].slice);
  return slices;
}

}  // namespace xsect
