// The function f_i of the Shepard interpolant (thesis ch. 1 §1.1) on a whole cutting plane: the
// signed Euclidean distance to the plane's section-contours, negative inside the sections, clamped
// above at `cap`; a plane without sections has f_i ≡ cap (the caller picks the cap per plane:
// the pipeline gives planes without sections the end margin, pipeline/smooth_stage.cpp).
//
// Why a cap: the interpolant averages the f_i of the planes that see x. Far from its contours a
// plane says only "outside, far"; an empty plane (a virtual end plane, or a slice that missed the
// object) has no contour at all and its distance would be infinite, which would make every point
// that sees it outside. Clamping every plane at one cap keeps their votes comparable.
//
// How it is evaluated: near the contours (within the band of the plane's SectionDistanceField,
// 3 voxels by default) the value is the band raster's, exact at its nodes; farther, a coarse raster
// over the part of the plane inside the grid holds b + E(y) - step/√2, where E is OpenCV's exact
// Euclidean distance transform (DIST_MASK_PRECISE) to the coarse nodes within the band b. At a
// coarse node this is within step/√2 of the true distance (the b-offset of the contours contains a
// node within √2·step of the point nearest to y); between nodes the bilinear interpolation of a
// 1-Lipschitz function adds at most step/√2 more. The error bound reported by `farErrorBound` is
// tested against the exact polygon distance (tests/test_shepard.cpp).
#pragma once

#include <cmath>
#include <vector>

#include "geometry/scene/section_distance_field.h"
#include "geometry/core/types.h"

namespace xsect {

struct PlaneDistanceFunction {
  float cap = 1.0f;          ///< f_i <= cap; empty planes: f_i ≡ cap (mm)
  SectionDistanceField far;  ///< coarse raster of the clamped distance (band = cap: its outside value)
};

/// @param near   the plane's band raster (sectionDistanceField of its sections).
/// @param plane  the plane (to find the part of it inside `grid`).
/// @param grid   the voxel grid the interpolant will be evaluated on.
/// @param cap    clamp, mm (> 0).
/// The coarse raster's step is twice the band raster's (its nodes are band-raster nodes).
PlaneDistanceFunction planeDistanceFunction(const SectionDistanceField& near, const Plane& plane,
                                            const GridSpec& grid, double cap);

/// f_i at plane coordinates (a, b).
inline float planeDistanceValue(const SectionDistanceField& near, const PlaneDistanceFunction& f,
                                double a, double b) {
  float v;
  if (near.sampleWithinBand(a, b, &v)) return v < f.cap ? v : f.cap;
  return f.far.sample(a, b);
}

/// Largest error of planeDistanceValue against the exact clamped distance, mm: 0 at band-raster
/// nodes, the band raster's bilinear error between them (at most step/√2), √2·(coarse step) beyond.
inline double farErrorBound(const PlaneDistanceFunction& f) { return std::sqrt(2.0) * f.far.step; }

/// The default cap: the radius of the disk with the area of the largest section, √(A/π) (mm), so
/// that no section's inside is clamped; `fallback` when there is no section.
double defaultDistanceCap(const std::vector<CuttingPlane>& planes, double fallback);

}  // namespace xsect
