// The sections of a closed triangle mesh by a plane (thesis ch. 1 §1: S_P = O ∩ P, O the solid
// the mesh bounds), as outer rings and holes in the plane's (u, v) frame. `xsect slice` turns a
// model organ into the cross-sections an acquisition at given poses would give (issue 18: plan
// slices on a model, close the loop on real shapes).
#pragma once

#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// @param mesh   closed (watertight) triangle mesh, world mm; orientation does not matter.
/// @param plane  cutting plane with its frame.
/// A vertex exactly on the plane is taken 1e-9 of the mesh's size off it on the normal's side, so
/// that where the plane runs through vertices (a face or an edge of the mesh in the plane) the
/// section is the one just behind the plane; each crossed triangle gives one segment, the
/// segments close into simple rings, and rings that would touch at such a vertex do not. Each
/// crossing point is computed once per edge, so both triangles of an edge share it.
/// Rings are nested by containment: a ring inside an even number of others is an outer contour
/// (counter-clockwise), inside an odd number a hole (clockwise). Rings without area (the plane
/// touches the mesh at a point or along a segment) are dropped. Empty when the plane misses it.
/// Throws std::invalid_argument when the crossings do not close (the mesh is not closed there) or
/// a ring crosses itself (the mesh intersects itself there).
std::vector<Section> meshSections(const TriangleMesh& mesh, const Plane& plane);

}  // namespace xsect
