// Where a plane was observed only in part (an image's rectangle, a probe's sector: docs/inputs.md: field
// of view), a section's contour may run along the border of what was seen rather than along the
// object. The sampling diagnosis (issue 18) leaves contour points near that border out of what
// it measures on the object's surface.
#pragma once

#include "geometry/core/types.h"

namespace xsect {

/// Whether p (plane coordinates, mm) lies within `tolerance_mm` of the edge of the part of the
/// plane that was observed, or outside it. Always false for a plane observed everywhere.
bool nearObservedEdge(const CuttingPlane& plane, const Vec2& p, double tolerance_mm);

}  // namespace xsect
