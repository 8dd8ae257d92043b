// Where to add slices (issue 18; thesis ch. 1 §2.3: the conditions bound the cells' heights).
// Greedy: take the cell with the worst ratio h_C / critical reach of the Density Condition while
// it is not shown everywhere, else of the Transversality Condition (the height alone where no
// critical value is known), cut it by a plane through the centre of its inscribed ball, oriented
// among 13 directions (the axes, the face and the body diagonals of the frame) to leave the smaller
// of the two halves' largest heights; then re-measure every listed cell that plane cuts and go on.
// The heights are exact (Chebyshev balls, cell_height.h) within the end planes' box.
#pragma once

#include <vector>

#include "geometry/core/types.h"
#include "geometry/sampling/sampling_conditions.h"

namespace xsect {

struct AdvisedSlice {
  Plane plane;              ///< through the cell's ball centre; u, v span it, mm
  int cell = -1;            ///< the diagnosis' cell it splits (index into SamplingDiagnosis::cells)
  double worst_before = 0;  ///< the worst ratio (or height, mm) before the slice
  double worst_after = 0;   ///< and after it, among the cells followed
  bool ratio = true;        ///< worst_* are ratios h_C / critical (false: heights, mm)
};

struct AdviceParams {
  int count = 10;                 ///< at most this many slices
  bool until_resolved = false;    ///< stop once every followed cell's ratio is below 1
  int followed_cells = 48;        ///< the worst cells followed
};

/// The 13 directions a cut is chosen among: the axes, the face and the body diagonals of the frame
/// (one of each ± pair), unit vectors.
std::vector<Vec3> adviceDirections();

/// @param planes  the planes the diagnosis was made with (end planes included).
/// @param lo, hi  the end planes' box, mm.
/// Deterministic.
std::vector<AdvisedSlice> adviseSlices(const std::vector<CuttingPlane>& planes, const SamplingDiagnosis& diagnosis,
                                       const Vec3& lo, const Vec3& hi, const AdviceParams& params);

}  // namespace xsect
