// Closing open cells (issue "open ends"): where a section lies on an unbounded cell of the
// arrangement, R (thesis Def. 16) is an infinite prism. The scene is closed within the thesis' own
// definitions by six virtual cutting planes with empty sections: the faces of the sections'
// bounding box pushed out by the end margin. R then ends half-way between an outermost section and
// the virtual plane beyond it.
#pragma once

#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// Axis-aligned world bounds of all sections of the planes, mm. Returns false if there is none.
bool sectionBounds(const std::vector<CuttingPlane>& planes, Vec3* min, Vec3* max);

/// Automatic end margin (mm): the median, over planes holding sections, of the gap from the
/// sections' centroid along the plane normal to the nearest other plane within 60° of parallel;
/// `fallback` where no plane has such a neighbour.
double automaticEndMargin(const std::vector<CuttingPlane>& planes, double fallback);

/// The six virtual empty planes bounding [min - margin, max + margin], normals pointing outward.
std::vector<CuttingPlane> endPlanes(const Vec3& min, const Vec3& max, double margin);

}  // namespace xsect
