// Gluing the cells of method 3 along one cutting plane (thesis ch. 3 §2, "Solidity and
// Topological Correctness"): the boundary of R'' within the plane. The two sides' cells triangulate
// the plane's sections differently, so their grounded triangles are not compared face by face:
// the plane's section-vertices are triangulated once (CGAL constrained Delaunay, in the plane's
// own coordinates), with the contour edges and the rim edges (grounded edges of the plane on which
// a non-grounded boundary triangle of either side stands) as constraints, so that the region each
// side's solid covers is a union of its triangles. A triangle inside the sections is a boundary
// face when exactly one side covers it (tested at its centroid), facing away from that side.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geometry/delaunay/section_vertices.h"

namespace xsect {

struct PlaneFootprint {
  /// Grounded triangles (point ids) of each side's kept tetrahedra: [0] negative side, [1] positive.
  std::array<std::vector<std::array<int, 3>>, 2> covered;
  std::vector<std::array<int, 2>> rims;  ///< rim edges, point ids
};

struct PlaneBoundary {
  std::vector<std::array<int, 3>> faces;  ///< oriented outwards; ids >= sv.points.size() are new
  std::vector<Vec3> new_points;           ///< where constraints crossed (id sv.points.size() + k)
};

/// @param plane  index of the plane in `planes` (and sv.sampled).
/// @param ids    the section-vertices lying on the plane, sorted.
/// @param firstNewId  the id the first new point takes.
PlaneBoundary planeBoundary(int plane, const std::vector<int>& ids, const PlaneFootprint& footprint,
                            const SectionVertices& sv, const std::vector<CuttingPlane>& planes, int firstNewId);

}  // namespace xsect
