// Virtual end planes and the automatic end margin (see end_planes.h).
#include "geometry/scene/end_planes.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/core/median.h"
#include "geometry/core/polygon.h"

namespace xsect {

bool sectionBounds(const std::vector<CuttingPlane>& planes, Vec3* min, Vec3* max) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  bool any = false;
  for (const auto& p : planes)
    for (const auto& s : p.sections)
      for (const auto& q : s.outer) {
        const Vec3 w = p.plane.toWorld(q);
        lo = lo.cwiseMin(w);
        hi = hi.cwiseMax(w);
        any = true;
      }
  if (any) {
    *min = lo;
    *max = hi;
  }
  return any;
}

double automaticEndMargin(const std::vector<CuttingPlane>& planes, double fallback) {
  std::vector<double> gaps;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const auto& pi = planes[i];
    if (pi.sections.empty() || pi.is_virtual) continue;
    Vec2 c = Vec2::Zero();
    double area = 0;
    for (const auto& s : pi.sections) {
      const double a = sectionArea(s);
      c += a * sectionCentroid(s);
      area += a;
    }
    if (area <= 0) continue;
    const Vec3 x = pi.plane.toWorld(c / area);
    double gap = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < planes.size(); ++j) {
      if (j == i || planes[j].is_virtual) continue;
      const double cosine = std::abs(planes[j].plane.normal.dot(pi.plane.normal));
      if (cosine < 0.5) continue;
      // distance along pi's normal from x to plane j
      const double t = std::abs(planes[j].plane.signedDistance(x)) / cosine;
      if (t > 1e-9) gap = std::min(gap, t);
    }
    if (std::isfinite(gap)) gaps.push_back(gap);
  }
  if (gaps.empty()) return fallback;
  return upperMedian(std::move(gaps));
}

std::vector<CuttingPlane> endPlanes(const Vec3& min, const Vec3& max, double margin) {
  std::vector<CuttingPlane> out;
  const char* names[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      CuttingPlane cp;
      cp.is_virtual = true;
      cp.name = std::string("end-plane ") + (side ? "+" : "-") + names[axis];
      Vec3 n = Vec3::Zero();
      n[axis] = side ? 1.0 : -1.0;
      Vec3 o = 0.5 * (min + max);
      o[axis] = side ? max[axis] + margin : min[axis] - margin;
      cp.plane.origin = o;
      cp.plane.normal = n;
      cp.plane.u = Vec3::Unit((axis + 1) % 3);
      cp.plane.v = n.cross(cp.plane.u);
      out.push_back(cp);
    }
  }
  return out;
}

}  // namespace xsect
