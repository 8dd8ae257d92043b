// A cell of the arrangement of the cutting planes as a convex polytope (thesis ch. 1 §2: the
// cells of the arrangement), from its sign vector and a point strictly inside it: CGAL's halfspace
// intersection of the planes that can reach it. A plane farther from the interior point than
// every vertex of the polytope of the nearer planes cannot cut it, so the nearer set is grown
// until none is left out: the cost follows the cell's facets, not all planes.
#pragma once

#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct CellPolytope {
  std::vector<Vec3> vertices;  ///< empty when the cell could not be built
  std::vector<int> planes;     ///< the planes a vertex lies on (its facets', nearest first), box faces aside
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  ///< bounding box of the vertices, mm
  bool empty() const { return vertices.size() < 4; }
};

/// @param planes    all planes, unit normals.
/// @param sides     the cell's side of each plane (+1: the normal's side), as cellHeight takes.
/// @param interior  a point strictly inside the cell, mm (otherwise: empty).
/// @param lo, hi    a box that closes the cell (the end planes' box, padded), mm.
CellPolytope cellPolytope(const std::vector<Plane>& planes, const std::vector<int>& sides, const Vec3& interior,
                          const Vec3& lo, const Vec3& hi);

}  // namespace xsect
