// The border of a plane's observed part (see observed_edge.h).
#include "geometry/sampling/observed_edge.h"

#include <algorithm>

#include "geometry/core/polygon.h"

namespace xsect {

bool nearObservedEdge(const CuttingPlane& plane, const Vec2& p, double tolerance_mm) {
  if (plane.observed_everywhere) return false;
  const PlaneRect& e = plane.extent;
  const double inside = std::min({p.x() - e.min.x(), e.max.x() - p.x(), p.y() - e.min.y(), e.max.y() - p.y()});
  if (inside < tolerance_mm) return true;
  for (const Ring& ring : plane.field_of_view)
    if (ringDistance(ring, p) < tolerance_mm) return true;
  if (!plane.field_of_view.empty()) {
    bool within = false;
    for (const Ring& ring : plane.field_of_view) within = within || ringContains(ring, p);
    if (!within) return true;
  }
  return false;
}

}  // namespace xsect
