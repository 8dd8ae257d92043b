// The height of a cell of the arrangement of the cutting planes (thesis ch. 1 §2.3, Def. 23):
// h_C = max over x in C of d(x, ∂C). For a convex cell this is the radius of its largest inscribed
// ball (its Chebyshev ball), found by the linear program
//     maximise r  subject to  σ_j (n_j · x − d_j) ≥ r  for every plane j,
// σ_j the side of plane j the cell lies on, n_j a unit normal. The Density Condition (C1) asks
// h_C < reach_C(O) of every cell; the Transversality Condition (C2) h_C < ½ (1 − sin α_C) reach_C.
//
// Generalisation written down: a cell that the planes do not close (or close only far away) is
// measured within a box (in practice the reconstruction's grid), i.e. h_C of C ∩ box; such a cell
// is reported `open` when the box limits its height (the same cell in a larger box has a larger
// ball), since then its true height may be larger and no condition may be taken as shown for it.
// A cell that does not meet the box is open with height 0.
#pragma once

#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct CellHeight {
  double height = 0;                ///< h_C, mm (0: the cell has no interior within the box)
  Vec3 centre = Vec3::Zero();       ///< centre of the inscribed ball, mm
  bool open = false;                ///< the box limits the height, or the cell misses the box
  std::vector<int> bounding_planes; ///< planes the ball touches (indices into `planes`)
};

/// @param planes  the cutting planes, real and virtual (unit normals: std::invalid_argument
///                otherwise).
/// @param sides   sides[j] = +1 when the cell lies on the side planes[j].normal points to, −1
///                otherwise; the same length as `planes` (std::invalid_argument otherwise).
/// @param lo, hi  the box the cell is measured within, mm (lo < hi componentwise).
/// Solved exactly (CGAL's linear programming solver on the planes' double coefficients) by
/// constraint generation: the program starts with the box alone and adds the plane its ball
/// crosses most deeply until the ball crosses none, so each program holds the cell's facets and
/// few others.
/// @param check_open  false: skip the second program that decides `open` (left false), for callers
///                    whose planes close every cell within the box (the end planes).
/// @param first       planes (indices) the program holds from the start, in this order: a guess at
///                    the facets (a neighbouring cell's bounding planes) saves the rounds that would
///                    find them. The height is the program's optimum whatever rows it holds (to the
///                    1e-12 of the box by which a ball may cross a plane it did not add); the
///                    centre, when several balls are largest, may depend on them.
CellHeight cellHeight(const std::vector<Plane>& planes, const std::vector<int>& sides, const Vec3& lo,
                      const Vec3& hi, bool check_open = true, const std::vector<int>& first = {});

}  // namespace xsect
