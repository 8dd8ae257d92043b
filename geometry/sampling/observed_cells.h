// The cells of the arrangement when each cutting plane P is replaced by its observed piece Ω_P
// (issue 20; docs/methods.md, "Observed pieces"): the Ω-cells are the connected components of the box less
// the union of the pieces. An Ω-cell is a union of cells of the whole planes' arrangement (thesis
// ch. 1 §2) joined across the parts of their faces that no slice observed, so it need not be
// convex. With every piece whole, the Ω-cells are the thesis' cells.
//
// Its height (Def. 23 with C an Ω-cell): for x in C, d(x, ∂C) = D_Ω(x) := min over the planes of
// d(x, Ω_P) (the end planes whole): the segment from x to its nearest point on the union of the
// pieces crosses no piece, so that point lies on ∂C. Hence h_C = max over C of D_Ω, and the
// lattice gives the bounds cell_scan.h gives for whole planes (D_Ω is 1-Lipschitz): below, max of
// D_Ω over C's lattice points; above, that max + ρ, or ρ.
//
// Which whole cells are joined is read on the scan's lattice: two lattice neighbours in different
// cells lie in one Ω-cell when the segment between them crosses no piece (each plane it crosses,
// it crosses outside that plane's piece); and so do the two cells on either side of each point of
// a plane just beyond its piece's edge (sampled along the edge at a quarter of the lattice
// spacing), where the passages narrower than the lattice run (between a piece's edge and a plane
// crossing its plane nearby). Definition written down: a passage no lattice edge and no such
// point meets (through a cell the lattice does not meet) is not seen, and the cells it joins count
// as separate Ω-cells (tests/test_observed_cells.cpp measures how often, against a finer lattice).
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/core/types.h"
#include "geometry/sampling/cell_scan.h"
#include "geometry/scene/observed_piece.h"

namespace xsect {

struct ObservedCells {
  int count = 0;                         ///< Ω-cells of the scanned cells and the cells given
  std::vector<int> cell_of_scanned;      ///< per scanned cell: its Ω-cell, numbered in scan order
  std::vector<int> cell_of_extra;        ///< per cell given (`extra`): its Ω-cell, numbered after
  /// Per Ω-cell: how many cells of the whole planes it joins (scanned, given, or met only beyond a
  /// piece's edge): 1 for a cell of the whole planes on its own.
  std::vector<int> members;
  std::vector<double> max_distance_mm;   ///< per scanned cell: max of D_Ω over its lattice points
  /// Per scanned cell: max over its lattice points of a lower bound of D_Ω (a field of view's
  /// distances are upper bounds, observed_piece.h: ObservedPiece::bounds); a lower bound of the
  /// height, equal to max_distance_mm for rectangles.
  std::vector<double> max_distance_lo_mm;
  std::vector<Vec3> farthest;            ///< per scanned cell: the first lattice point reaching it
  std::vector<double> distance_mm;       ///< per lattice point: D_Ω, mm (−1 outside the box)
  std::int64_t unobserved_crossings = 0; ///< lattice edges that join two cells through no piece
};

/// @param scan    the lattice scan of the whole planes' cells (cell_scan.h), over the end box.
/// @param planes  the planes scanned, in the scan's order (unit normals), and their cell keys.
/// @param pieces  their observed pieces (observed_piece.h), one per plane.
/// @param extra   keys of cells the lattice does not meet that need their Ω-cell (the cells only
///                section points meet): joined as the points beyond the pieces' edges say.
/// Parallel over lattice rows; the result does not depend on the thread count.
ObservedCells observedCells(const CellScan& scan, const std::vector<Plane>& planes, const CellKeys& keys,
                            const std::vector<ObservedPiece>& pieces, const std::vector<std::uint64_t>& extra = {});

}  // namespace xsect
