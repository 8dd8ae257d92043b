// Method 3 within one cell: tunnels of R''_C that its sections do not carry, cut (not the
// thesis' step; thesis ch. 1 §4.4, Def. 25 and the remark before it, for what it rests on).
// The thesis' guarantees within a cell C rest on lift(S_C) having contractible components ("very
// common in practice, where the sections are contractible and sufficiently close to each other"):
// then O_C has trivial π1, and a tunnel of the reconstruction inside one cell is the failure of
// Fig. 1.11 (two sections whose connections close a loop that the object does not have). The
// pruned Delaunay structure has such tunnels between sparse planes: three sections joined in
// pairs around a middle whose tetrahedra touch each section at a point or an edge only (removed
// by the solidity conditions, Def. 50), or five sections of a torus' cell all joined in pairs.
// Here, while the kept tetrahedra of C have a tunnel (b1 = b0 - χ + b2 > 0; b2 counts the other
// tetrahedra that do not reach the hull) and the graph H_C of the pairs of sections on different
// planes they join has a cycle, the pairs on a cycle are tried by the volume of the tetrahedra
// joining them (least first; ties: the lowest pair): every tetrahedron of D1 with a vertex in
// each of the two sections is left out, and steps 2-3 run again. The cut is kept when b1 went
// down, b0 and b2 did not go up and the cell's footprint on its faces (its grounded triangles:
// components through shared edges and Euler characteristic) is as it was; else it is undone and
// the next pair tried. A cut footprint would trade the cell's tunnel for one through the gluing
// (a torus cut by 6 random planes: a cut splitting the footprint left b1 as it was). Tunnels with
// H_C a forest (a section with a hole, a tube between annuli; the two contacts of Fig. 1.11), or
// that the footprint carries, are left: the sections' own holes carry them, or no pair decides.
// Measured on 29 sparse configurations (bench/sparse_comparison.py): every run whose b1
// exceeded the truth's had exactly that excess in such in-cell tunnels. Where the assumption
// fails, a true tunnel is cut: a torus whose hole no plane crosses (6 or 9 random planes, seed 5)
// has it inside one cell, and loses it.
#pragma once

#include <vector>

#include "geometry/delaunay/cell_complex.h"

namespace xsect {

struct CellCycleCuts {
  int pairs = 0;       ///< section pairs cut
  int tunnels = 0;     ///< by how much the cell's b1 went down
  int tetrahedra = 0;  ///< tetrahedra of D1 (not flat, external or unjoined) left out
};

/// @param c          a pruned cell (pruneCell ran); `cycle_cut`, `kept` and d1-d3 are updated.
/// @param sectionOf  per section-vertex, the flat id of its section (-1: none).
/// @param points     the section-vertices (positions, mm; planes[0], their section's plane).
/// @returns what was cut.
CellCycleCuts cutCellCycles(CellComplex& c, const std::vector<int>& sectionOf,
                            const std::vector<SectionVertex>& points);

}  // namespace xsect
