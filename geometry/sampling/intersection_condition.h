// The Intersection Condition (thesis ch. 1 §4.4, Def. 25) shown on the data, per cell, for
// method 1. The thesis' sufficient form (§4.4): every connected component of lift(S_C) is
// contractible. Then π1(lift(S_C)) is trivial, so the lift map L_* is onto (Def. 25 holds: under
// the Separation Condition the sections whose lifts meet are joined in M_C, and every loop is
// trivial), and with the Separation Condition R is homotopy equivalent (Thm 12, 14),
// homeomorphic and isotopic (Thm 16) to O.
//
// lift(S_C) is the union of the lifts of the pieces of the sections on ∂C (a piece: a connected
// component of a section ∩ a face of C), each homeomorphic to its piece. The components of such a
// union are contractible when (peeling leaves off a tree, Mayer-Vietoris):
//  (i)   every piece is simply connected. A section ∩ a convex face has simply connected
//        components unless one of the section's holes lies wholly inside the face (no plane
//        separates the hole's vertices);
//  (ii)  every nonempty lift(P) ∩ lift(P') is connected. It lies on the ridge of C's medial axis
//        between the two faces, where it is the intersection of two simply connected planar sets
//        (pulled back by the two orthogonal projections), so its components are simply connected;
//  (iii) the graph of the pieces, with one edge per component of those intersections, is a forest
//        (so no three lifts meet either).
// The pieces and the components of (ii) are found on the arrangement's section points (lattice
// samples at spacing s, contour vertices, trace points), points within 1.5 s taken as connected:
// like the connectivity graphs, the check holds at the sampling's resolution (a connection or a
// gap narrower than s can be missed). A component of lift(P) ∩ lift(P') is counted on the points
// of P whose method-1 lift lands in P' (their lifts are the intersection, projected on P's plane),
// and from P' likewise; the larger count is taken. A cell is not shown (left undetermined) when
// any of (i)-(iii) fails, or when a lift lands where no point of the section it lands in lies
// within 1.5 s.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/arrangement/section_arrangement.h"
#include "geometry/core/types.h"

namespace xsect {

struct IntersectionConditionCheck {
  std::vector<std::uint8_t> shown;  ///< per arrangement cell: 1 when the condition is shown there
  int cells_with_holes = 0;         ///< a piece with a hole (i)
  int cells_with_cycles = 0;        ///< the pieces' graph has a cycle or a disconnected intersection (ii-iii)
  int cells_unlocated = 0;          ///< a lift landing far from every point of its section
};

/// @param planes        the planes the arrangement was built on.
/// @param lift_section, lift_length_mm  method 1's lifts of the arrangement's points
///                      (ConnectivityGraphs, connectivity_graph.h): 2 per point; other sizes
///                      show nothing.
IntersectionConditionCheck checkIntersectionCondition(const std::vector<CuttingPlane>& planes,
                                                      const SectionArrangement& arrangement,
                                                      const std::vector<std::int32_t>& lift_section,
                                                      const std::vector<float>& lift_length_mm);

}  // namespace xsect
