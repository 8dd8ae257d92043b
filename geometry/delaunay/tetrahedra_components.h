// The connected components of a union of closed tetrahedra (method 3's R'', delaunay_reconstruction.h),
// read from the tetrahedra themselves: two tetrahedra are joined when they share a vertex, or two
// vertices at the same position (exactly equal coordinates: the tetrahedra of one triangulation,
// and of two cells glued along a plane, carry the same section-vertices as the same doubles). What the Betti number b0 of the mesh
// bounding R'' is checked against (issue 14: the mesh written bounds the solid reported). Where
// the mesh opened pinches (pieces touching at a point or along an edge get a copy of the vertex
// each, delaunay_reconstruction.h), each extra copy may split one more piece off: the mesh then
// has between `components` and `components + copies` outer surfaces.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geometry/core/types.h"
#include "geometry/delaunay/tetrahedron_set.h"

namespace xsect {

/// @param tetrahedra  #T tetrahedra on their vertex table (world coordinates, mm).
/// @returns the number of classes of tetrahedra under "share a vertex position" (0 for none).
int tetrahedraComponents(const TetrahedronSet& tetrahedra);

/// Vertices of `mesh` beyond the first at their position (0 when every position is held once):
/// for method 3's mesh, the copies its opened pinches added.
std::int64_t repeatedVertexCopies(const TriangleMesh& mesh);

}  // namespace xsect
