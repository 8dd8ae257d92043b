// A point strictly inside a cell of the arrangement, and the cell's sign vector, for the
// computations that need the cell as a region (its polytope: method 2's h'_C, section_cell_height.h;
// R_C's topology, intersection_condition.h). A cell holds a lattice point off every plane, or its
// Chebyshev ball (cell_height.h) gives one; a cell met by no lattice point takes its sign vector
// from the section point that keyed it (sampling_conditions.h).
#pragma once

#include <vector>

#include "geometry/core/types.h"
#include "geometry/sampling/cell_scan.h"
#include "geometry/sampling/sampling_conditions.h"

namespace xsect {

/// The section point that keyed an arrangement cell met by no lattice point: its plane and the
/// cell's side of it, for a trace point also the plane it lies on and the side taken, and whether
/// it lies off every other plane (then its other signs are not rounding's choice).
struct KeyPoint {
  int plane = -1, side = 0;
  int trace_plane = -1, trace_side = 0;
  bool generic = false;
  /// The cell's sign vector as this point gives it.
  std::vector<int> sides(const CellKeys& keys, const Vec3& x) const;
};

enum class Interior { found, none, unknown };

/// The cell's sign vector and a point strictly inside it: the lattice point or ball centre it holds
/// when that lies off every plane (its distance to them, height_lo_mm, > 0), else the centre of its
/// Chebyshev ball, which must lie in the cell keyed. `none`: the exact program finds no ball (beyond
/// rounding) in the box and the key came from a point on several planes at once (a fan's axis),
/// whose signs against them rounding chose: no open region has them, so the cell holds nothing of
/// the object or of R, its points lying on the closures of the cells around. `unknown`: no interior
/// point found otherwise (nothing may be shown there).
/// @param keyPoints  per arrangement cell, the point that keyed it.
/// @param lo, hi     the box closing the cells (the end planes' box, padded), mm.
Interior cellInterior(const CellSampling& c, const std::vector<Plane>& ps, const CellKeys& keys,
                      const std::vector<KeyPoint>& keyPoints, const Vec3& lo, const Vec3& hi,
                      std::vector<int>* sides, Vec3* interior);

}  // namespace xsect
