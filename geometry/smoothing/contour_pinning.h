// Pinning the section-contours on a sampled implicit function (thesis ch. 1 §1.1, Property 3:
// f|_{P_i} = f_i, so the zero set of f meets each plane exactly in its sections).
//
// On a grid, f is only known at voxel centres, and its zero set is read by trilinear
// interpolation. Where f has a feature narrower than a voxel beside a plane, that reading misses
// the contour although f itself passes through it. The case met in practice is Shepard's
// interpolant with p = 1 beyond the outermost plane of a stack: the plane's own extrusion
// outweighs its neighbours', the solid bulges past the neighbouring planes' contours between
// them and dips back onto each contour within a fraction of a voxel of its plane (on a torus cut
// 12 times per axis, 1.9% of the contour samples were read more than half a voxel off, at most 0.67
// voxel).
//
// pinSectionContours samples every contour of every plane holding sections (step: a quarter
// voxel) and reads f there trilinearly. Where it reads more than `tolerance_mm` inside (the solid
// bulges past the contour), the eight voxels around the sample take the plane's own value f_i at
// their projection (the signed distance, in the plane, to its contours); a voxel asked for by
// several planes takes the nearest one's value. Only those voxels change. Not pinned, and counted:
//  - samples read more than the tolerance outside: the solid does not reach the contour there
//    (e.g. it misses a thin section); pinning the rim alone would make a ring or a loose disc;
//  - samples with another plane holding sections within a voxel (a dense sweep): the grid cannot
//    hold both planes' contours, which differ by their noise.
// Samples where the plane was not observed (`observed` false: a contour following an image's
// edge, beyond its observed piece, is where the image ends, not the object) are not read.
// Deterministic; parallel over planes.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct ContourPinning {
  std::int64_t samples = 0;         ///< contour samples read
  std::int64_t samples_pinned = 0;   ///< read more than the tolerance inside: pinned
  std::int64_t samples_outside = 0;  ///< read more than the tolerance outside: left alone
  std::int64_t samples_crowded = 0;  ///< more than the tolerance inside, another plane within a voxel
  std::int64_t voxels_pinned = 0;    ///< voxels given f_i
  double worst_before_mm = 0;       ///< largest |trilinear f| at a sample, before pinning
};

/// @param field         f on the grid (negative inside); voxels around off samples are rewritten
/// @param planes        the cutting planes; those with sections are pinned
/// @param plane_value   f_i(a, b) of plane i at plane coordinates (a, b), mm
/// @param tolerance_mm  largest |f| accepted at a contour sample (>= 0), mm
/// @param observed      optional: whether plane i was observed at plane coordinates (a, b) (absent:
///                      everywhere)
ContourPinning pinSectionContours(ScalarField& field, const std::vector<CuttingPlane>& planes,
                                  const std::function<double(std::size_t, double, double)>& plane_value,
                                  double tolerance_mm,
                                  const std::function<bool(std::size_t, double, double)>& observed = {});

}  // namespace xsect
