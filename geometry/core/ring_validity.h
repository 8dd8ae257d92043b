// Degenerate contours (issue 15): repeated vertices, rings without area (the section of a tangent
// plane: a point or a segment) and self-intersecting rings, decided with exact predicates (CGAL)
// before any algorithm meets them.
#pragma once

#include "geometry/core/types.h"

namespace xsect {

/// The ring with consecutive repeated vertices removed (also the last one when it repeats the
/// first).
Ring withoutRepeatedVertices(const Ring& ring);

/// True when no two edges of the ring meet except consecutive ones at their shared vertex
/// (CGAL::is_simple_2 with exact predicates, O(n log n)). Rings of fewer than 3 vertices are not
/// simple.
bool ringIsSimple(const Ring& ring);

}  // namespace xsect
