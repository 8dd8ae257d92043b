// The connected components of a union of closed tetrahedra (method 3's R'', delaunay_reconstruction.h),
// read from the tetrahedra themselves: two tetrahedra are joined when they share a vertex, or two
// vertices at the same position (exactly equal coordinates: the tetrahedra of one triangulation,
// and of two cells glued along a plane, carry the same section-vertices as the same doubles). What the Betti number b0 of the mesh
// bounding R'' is checked against (issue 14: the mesh written bounds the solid reported). Where
// the mesh opened pinches (pieces touching at a point or along an edge get a copy of the vertex
// each, delaunay_reconstruction.h), each extra copy may split one more piece off: the mesh then
// has between `components` and `components + copies` outer surfaces. A component none of whose
// tetrahedra bounds volume, as the boundary's repairs measure it, has no surface and is not
// counted.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geometry/core/types.h"
#include "geometry/delaunay/boundary_repairs.h"
#include "geometry/delaunay/tetrahedron_set.h"

namespace xsect {

/// @param tetrahedra  #T tetrahedra on their vertex table (world coordinates, mm).
/// @param bounds      the boundary's repairs: a class none of whose tetrahedra bounds volume (each
///                    has an edge shorter than the weld, its vertices welded into fewer than four,
///                    or is thinner than flat_thickness_mm on average, 3|V| / A with A the area of
///                    its four faces) is not counted: the mesh has no surface for it. Measured: a
///                    lone needle of three points 0.001 mm apart (weld 0.002 mm), two crossing
///                    sweeps with enforced conformity. Zeros: every class counts.
/// @returns the number of classes of tetrahedra under "share a vertex position" (0 for none).
int tetrahedraComponents(const TetrahedronSet& tetrahedra, const BoundaryTolerances& bounds = {});

/// Vertices of `mesh` beyond the first at their position (0 when every position is held once):
/// for method 3's mesh, the copies its opened pinches added.
std::int64_t repeatedVertexCopies(const TriangleMesh& mesh);

}  // namespace xsect
