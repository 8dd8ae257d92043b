// Repairs of method 3's glued boundary into a closed 2-manifold (thesis ch. 3 §2, "Solidity and
// Topological Correctness": gluing the cells' pieces along the planes can leave singularities;
// see delaunay_reconstruction.h for where each repair is measured to be needed). Plain data in and
// out: faces are triangles of point ids, oriented outwards; positions are world coordinates, mm.
// Every function works on the whole face list; the same input gives the same output (method 3's
// determinism tests run through all of them).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <unordered_map>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// What the repairs below treat as one point (weldNearVertices) and as no volume (dropFlatShells),
/// mm; DelaunayReconstruction::tolerances holds the ones a run used, and tetrahedraComponents counts
/// the solid with them.
struct BoundaryTolerances {
  double weld_mm = 0;            ///< vertices nearer than this are welded into one
  double flat_thickness_mm = 0;  ///< a shell thinner than this on average (3 volume / area) is dropped
};

/// The number of faces on each edge (edgeKey) of `faces`.
std::unordered_map<std::uint64_t, int> edgeUses(const std::vector<std::array<int, 3>>& faces);

/// Splits faces at T-junctions: where a face's edge a→b is in an odd number of faces while a face
/// on the other side leaves b towards a point m inside the segment (points of a trace line shared
/// by the cells' triangulations and the plane's, collinear up to rounding; the plane's constraints
/// crossing), the face (a, b, c) becomes (a, m, c) and (m, b, c); the next pass splits (a, m, c)
/// again where several such points lie on the segment. Repeats until no such edge remains.
void splitTJunctions(std::vector<std::array<int, 3>>& faces, const std::function<Vec3(int)>& at);

/// Welds boundary vertices nearer than `tolerance` (a contour crossing sampled on two planes and
/// a corner of three planes can nearly coincide where the planes meet at the surface): in each
/// cluster the point on the most planes (`planesOf`; then the smallest id) takes the others that
/// lie on none but its planes (`covers`), so that no point leaves a plane it lies on; triangles
/// that lose a vertex go, and pairs of triangles on the same three vertices with opposite
/// orientations cancel. Returns the vertices welded.
int weldNearVertices(std::vector<std::array<int, 3>>& faces, const std::vector<Vec3>& positions, double tolerance,
                     const std::function<int(int)>& planesOf, const std::function<bool(int, int)>& covers);

/// Closes each hole bounded by three or four directed edges a→b→c(→d)→a that are each in an odd
/// number of faces and whose vertices all lie on one plane (`onOnePlane`), with the reversed cycle,
/// unless a face on three of its vertices exists (a lone triangle is its own cycle: its reverse
/// would only hide it as a sheet of no volume). A quadrilateral is split along the diagonal that
/// is no edge of the mesh yet and whose two triangles face the same way (a - c when both do). An
/// odd edge closes at most one hole. Returns the holes closed.
int closeFlatHoles(std::vector<std::array<int, 3>>& faces, const std::vector<Vec3>& positions,
                   const std::function<bool(const std::vector<int>&)>& onOnePlane);

/// Drops each component of the boundary (faces joined through shared vertices) whose mean
/// thickness 3|V| / A (V its signed volume about one of its points, A its area) is below
/// `thickness`: it bounds no volume. Measured: a sliver tetrahedron (four section-vertices on
/// different planes but nearly coplanar) that opening the pinches parted from the solid, or such a
/// void; a flat sheet lying twice on a plane with opposite orientations (V = 4e-16 mm³ for
/// A = 0.4 mm²); two slivers along nearly collinear points of a plane's triangulation (A = 5e-4 mm²,
/// open). An open component (an edge in an odd number of its faces) is dropped only when its area
/// is below `openArea`: a larger one is a defect that open_edges must report, not hide.
/// Returns the components dropped.
int dropFlatShells(std::vector<std::array<int, 3>>& faces, const std::vector<Vec3>& positions, double thickness,
                   double openArea);

/// Pairs of faces (indices) across an edge: the faces of one sheet there.
using FacePairs = std::vector<std::array<int, 2>>;

struct OpenedPinches {
  int edges = 0;       ///< edges in 4, 6, ... faces whose sheets were separated
  int vertices = 0;    ///< vertices given more than one copy
};

/// Resolves the pinches of the boundary into a 2-manifold. Where 2k > 2 faces meet at an edge
/// (solid wedges touching along it: around a branching line inside a terminal section, Fig. 3.14,
/// or where the pieces of two cells meet on a trace), the faces are paired across the empty
/// wedges, so that the wedges stay joined along the edge, as Def. 50 counts a shell whose runs all
/// reach the section. Then every vertex gets one copy per umbrella (the faces around it joined
/// through such pairs): pieces touching at a single point are separate.
/// An edge that joining leaves singular at both ends (a branching line crossing a section from
/// contour to contour as one Delaunay edge, with no point inside the section to part the sheets
/// at) is split at its midpoint (a point of the edge: the surface does not move; for a grounded
/// edge, inside the section, Def. 47) and the pass repeated once (`splitting` false): the
/// midpoint's copies part the flat sheet from the wedges' as the thickened plane of Fig. 3.8b
/// would, and the wedges stay joined (R'' is their union). Only an edge still singular then is
/// paired apart.
/// `given`, `givenChoices`: face pairs and the two pairings of singular edges fixed in advance
/// (the split pass's; see there), used as they are instead of pairs by angle.
OpenedPinches openPinches(std::vector<std::array<int, 3>>& faces, std::vector<Vec3>& positions, bool splitting = true,
                          const std::unordered_map<std::uint64_t, FacePairs>& given = {},
                          const std::map<std::uint64_t, std::array<FacePairs, 2>>& givenChoices = {});

}  // namespace xsect
