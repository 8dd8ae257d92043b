// Method 2's height of a cell, h'_C (thesis ch. 2 §3, Def. 31), bounded from above:
//     h'_C = max over A in S_C of max over x in V_C(A) of d(x, np'_A(x)) = max over x in C of d(x, S_C),
// since the Voronoi cells V_C(A) of the sections on ∂C cover C and np'_A(x) is x's nearest point of
// the sections there. Method 2's conditions (C'1) h'_C < reach_e and (C'3) h'_C < ½(1 − sin α_a)
// reach(a) need this upper bound to be shown.
//
// How: the cell is built as a convex polytope (cell_polytope.h) around a point strictly inside it. d(x, S_C) is bounded
// from above by u(x), the distance to the nearest of given points of S_C (contour vertices, trace
// points, lattice samples inside the sections: every one lies in S_C, so u ≥ d). u is 1-Lipschitz,
// so over a box of centre c and half diagonal r, d ≤ u(c) + r. Boxes are split (branch and bound,
// largest bound first) within the polytope's bounding box; a box whose ball lies outside one of
// the cell's planes is dropped (the cell is convex). The bound returned is the largest bound of
// the boxes left, so it is ≥ h'_C whatever the stopping point; it exceeds h'_C by at most the
// resolution plus the gaps between the given points (the section sampling).
#pragma once

#include <limits>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct SectionHeightParams {
  int max_boxes = 4000;            ///< boxes split at most, per cell
  double relative_resolution = 0.05;  ///< stop splitting boxes whose half diagonal is below this fraction of their bound
};

struct SectionHeightBound {
  double upper_mm = std::numeric_limits<double>::infinity();  ///< ≥ h'_C (+inf: not bounded)
  Vec3 farthest = Vec3::Zero();  ///< centre of the box holding the bound (where h'_C may be reached)
  int boxes = 0;                 ///< boxes split
};

/// @param planes    all planes (cutting planes and end planes), unit normals.
/// @param sides     the cell's side of each plane (+1: the normal's side), as cellHeight takes.
/// @param interior  a point strictly inside the cell (e.g. a lattice point of it, or its Chebyshev
///                  ball's centre), mm.
/// @param lo, hi    the end planes' box, mm (it closes the cell as cellHeight's box does).
/// @param section_points points of S_C (world, mm); empty: +inf (no section, h'_C undefined).
/// @param target_mm stop as soon as the bound is below this (0: refine to the resolution).
/// @param resolution_mm  boxes of half diagonal below this are not split, mm (> 0).
SectionHeightBound sectionHeightBound(const std::vector<Plane>& planes, const std::vector<int>& sides,
                                      const Vec3& interior, const Vec3& lo, const Vec3& hi,
                                      const std::vector<Vec3>& section_points,
                                      double target_mm, double resolution_mm,
                                      const SectionHeightParams& params = {});

}  // namespace xsect
