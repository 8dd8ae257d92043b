// Crossing contours made simple (issue 49): the rings of one section set (one plane, one
// material) that cross themselves or each other, or touch at a vertex, turned into simple rings
// that bound the same region by a stated rule, with exact arithmetic (CGAL's 2D arrangement of
// the rings' segments, exact constructions; the new vertices are rounded to doubles at the end).
//
// The rule, "positive winding of the oriented lobes":
//  1. a ring that crosses or touches itself stands for the region its even-odd rule gives (each
//     lobe of a figure eight once, a loop traced twice not at all): that region's boundary loops;
//  2. the loops of outer rings are oriented counter-clockwise, those of holes clockwise (a hole's
//     region counts -1), and the section set is the region of positive winding number of all of
//     them: overlapping outer rings join (their union), overlapping holes are removed together,
//     a hole reaching outside its outer ring removes only what lies inside it, an island in a hole
//     stays, and a hole inside no outer ring removes nothing.
// For rings that are already simple and pairwise disjoint (touching at no point) this is the
// region the thesis' sections are (outer rings minus their holes), so they are returned as given.
// The boundary of the region is traced with the region on the left: rings touching at a vertex
// come out as separate rings meeting at that vertex (each simple).
#pragma once

#include <string>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct RingRepair {
  std::size_t outers_in = 0, holes_in = 0;  ///< the rings given
  std::vector<Ring> outers;  ///< counter-clockwise, simple
  std::vector<Ring> holes;   ///< clockwise, simple
  bool changed = false;      ///< false: the input rings were simple and disjoint, returned as given
  double area_before = 0;    ///< Σ |outer areas| − Σ |hole areas| of the input, mm² (as if simple)
  double area_after = 0;     ///< the region's area, mm²
};

/// Whether the rings are each simple and pairwise disjoint but for touching at shared vertices (no
/// crossing, no edge along another, no vertex inside another ring's edge), with exact predicates
/// (a sweep over all their segments, O(n log n)).
bool ringsAreSimpleAndDisjoint(const std::vector<Ring>& rings);

/// "<where>: crossing contours made simple (N outer rings and M holes -> N' and M';
/// area A -> B mm², by the positive winding of their oriented lobes)": the warning of a repair.
std::string repairWarning(const std::string& where, const RingRepair& r);

/// The region of `outers` and `holes` by the rule above, as simple rings. Rings of fewer than
/// three distinct vertices are ignored. Exact: O((n + k) log n) for n segments crossing k times.
/// Throws std::invalid_argument when the rings, rounded to doubles, would cross again.
RingRepair repairRings(const std::vector<Ring>& outers, const std::vector<Ring>& holes);

}  // namespace xsect
