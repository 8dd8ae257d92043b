// Samples of the medial axis of a shape given by its exact signed distance φ (thesis ch. 1 Def. 19,
// the Separation Condition: MA_i(∂O) ⊂ R and MA_e(∂O) ∩ R = ∅). Away from the medial axis φ is
// differentiable with |∇φ| = 1; across it the gradient turns, so a central difference of step h
// shrinks: |Δφ| / 2h < `ridge` (< 1) at a lattice point means a medial point lies within about h,
// with its two nearest boundary directions at an angle of at least 2·acos(ridge). Points closer
// than `margin` to the boundary are left out (where the medial axis meets creases of the boundary
// its samples say nothing about a reconstruction's separation). This samples the "λ-medial axis"
// (the part whose nearest points spread), which is what a discrete check can see.
#pragma once

#include <functional>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct MedialAxisSamples {
  std::vector<Vec3> interior;  ///< φ < 0: samples of MA_i
  std::vector<Vec3> exterior;  ///< φ > 0: samples of MA_e within the box
  double spacing_mm = 0;
};

/// @param sdf      exact signed distance, negative inside (thread-safe).
/// @param lo, hi   the box sampled, mm.
/// @param spacing  lattice step h, mm (> 0).
/// @param ridge    gradient threshold in (0, 1).
/// @param margin   least |φ| of a sample, mm.
/// Deterministic; parallel over lattice planes.
MedialAxisSamples medialAxisSamples(const std::function<double(const Vec3&)>& sdf, const Vec3& lo, const Vec3& hi,
                                    double spacing, double ridge, double margin);

}  // namespace xsect
