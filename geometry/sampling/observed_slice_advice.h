// Where to add slices when the cells are the observed pieces' (docs/methods.md, "Observed pieces";
// observed_cells.h): the greedy of slice_advice.h on the Ω-cells, read on the diagnosis' lattice.
// An advised slice is an image over the end planes' box (the stage writes it so, two pixels wider:
// its piece is eroded by one), so it lowers every lattice point's distance to the pieces to
// min(D_Ω(x), d(x, Q)).
// Greedy: take the Ω-cell with the worst ratio (height / critical value of the Density Condition
// while it is not shown everywhere, else of the Transversality Condition; the height alone where
// no critical value is known) among those not shown satisfied, those holding sections first; cut
// it by the plane through its deepest lattice point, oriented among the 13 directions of
// slice_advice.h to leave the least largest distance over its points; lower every point's
// distance and go on. Heights are the lattice's upper bounds (max + ρ, cell_scan.h); an Ω-cell is
// not split by the planes added (its height stays the largest over all its points: an upper
// bound of its parts').
#pragma once

#include <vector>

#include "geometry/sampling/sampling_conditions.h"
#include "geometry/sampling/slice_advice.h"

namespace xsect {

/// @param diagnosis  a diagnosis on observed pieces (observed_distance_mm not empty).
/// Deterministic (parallel over directions and points, each result written in its own place).
std::vector<AdvisedSlice> adviseObservedSlices(const SamplingDiagnosis& diagnosis, const AdviceParams& params);

}  // namespace xsect
