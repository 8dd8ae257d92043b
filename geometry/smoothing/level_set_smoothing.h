// @brief The smoothing step of thesis ch. 1 §1 ("the reconstructed object may exhibit a jagged and
// unnatural appearance ... a smoothing step should be performed", Fig. 1.3, after Liu et al. 2008)
// done on the voxel solid itself: mean-curvature flow of R (method 1) or R' (method 2) as an
// OpenVDB narrow-band level set, with the values on the planes that hold sections pinned to f_i, so
// that the smoothed surface still passes through the section-contours. Unlike Shepard's interpolant
// (shepard_interpolant.h), whose zero set may join the sections differently from the method, this
// starts from the method's solid and can be stopped before the flow changes its connectivity
// (`keeps`).
//
// The algorithm, on the lattice of the input grid (voxel (i, j, k) centred at origin + voxel·(i,j,k)):
//  1. Re-distancing. The input's values are only a sign plus a clamped approximation of distance;
//     OpenVDB's fast sweeping (tools::sdfToSdf), over the voxels within half_width_voxels + 1 of a
//     sign change, turns them into the signed Euclidean distance to their zero crossing (linear
//     between voxel centres), keeping every voxel's sign. A narrow band of half_width_voxels is
//     kept.
//  2. Holding. Each voxel whose centre x is within hold_mm of a plane with sections takes the value
//     f_i(np_i(x)) of its nearest such plane P_i (ties: lowest index): the signed distance, in the
//     plane, from x's projection to the section-contours. Exact on the plane, and the distance to
//     the surface where the surface crosses the plane at a right angle. Its sign is the input's
//     (|f_i| with the input's sign, at least 0.01 voxel, where the two disagree: the topology
//     repair of sampled_reconstruction.h or a plane crossing), so the solid of step 0 is exactly
//     the input's solid.
//  3. Flow. Each iteration is one explicit step of mean-curvature flow (tools::LevelSetFilter::
//     meanCurvature, dt = voxel²/3) with an alpha mask that is 0 on held voxels, followed by
//     OpenVDB's interface tracking (band rebuild and renormalisation); the held values, which the
//     renormalisation would move, are written back after every step.
//     Why mean curvature rather than Laplacian flow: the Laplacian equals the mean curvature only
//     where |∇φ| = 1, and the held values, constant along the plane normal, are not a 3D distance;
//     mean-curvature flow moves the zero set by its curvature whatever the scaling of φ around
//     it. And it costs no more: the interface tracking after each step (band dilation, three
//     renormalisation passes, trimming) dominates both (measured on an 88×88×94 grid, 2 busy cores:
//     0.18-0.21 s per mean-curvature step, 0.20-0.25 s per Laplacian step).
//  4. Connectivity. After every step the voxel solid {value < 0} is given to `keeps`; the flow
//     stops at the first step it rejects and the previous step is returned. Mean-curvature flow
//     changes topology by pinching necks and removing thin parts, which it never undoes, so the
//     step before the first rejection is, in practice, the most-smoothed acceptable one; checking every step costs one
//     dense copy and one call of `keeps` per step (no snapshots, no re-runs as a bisection would
//     need).
//
// Deterministic: the same bytes for any TBB thread count. Every OpenVDB pass used (fast sweeping:
// per-voxel updates along diagonal slices, whose face neighbours lie in the neighbouring slices; the
// filter and the tracker: per-voxel updates into a second buffer; dilation, trimming, pruning; min /
// max reductions) computes each voxel from values that do not depend on the scheduling (tested:
// 1 and 2 threads give identical bytes).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "geometry/scene/section_distance_field.h"
#include "geometry/core/types.h"

namespace xsect {

struct LevelSetSmoothingParams {
  /// Mean-curvature flow steps (>= 0), each of dt = voxel²/3: a sphere of radius r (mm) shrinks by
  /// about 2·voxel²/(3r) per step, a one-voxel stair step is rounded off in a few steps.
  int iterations = 8;
  /// Voxels whose centre is within this distance (mm, >= 0) of a plane holding sections keep the
  /// value f_i. Empty = half a voxel diagonal, √3/2 · voxel: then every voxel whose cube meets the
  /// plane is held, so the held layer separates the two sides of the plane.
  std::optional<double> hold_mm;
  /// Half-width of the narrow band in voxels (>= 2; OpenVDB's level-set tools use 3): values are
  /// signed distances within it and ±half_width_voxels·voxel beyond.
  int half_width_voxels = 3;
};

struct LevelSetSmoothing {
  /// Dense, on the input's grid, negative inside the smoothed solid: signed distance in mm within
  /// the band, ±band (half_width_voxels · voxel) beyond, the sign correct everywhere.
  ScalarField field;
  /// Steps of flow in `field`: params.iterations, or fewer when `keeps` rejected the next step.
  int iterations_applied = 0;
  /// Voxels held to f_i (within hold_mm of a plane with sections), in or out of the band.
  std::int64_t held_voxels = 0;
};

/// @param solid   the method's field on a grid (negative inside R or R'), e.g.
///                SampledReconstruction::field; its outermost voxel layer should be outside.
/// @param planes  the cutting planes (geometry/core/types.h); only planes with sections are held.
/// @param near    one SectionDistanceField per plane, same order (section_distance_field.h): f_i
///                in plane coordinates, exact within its band, sign everywhere; read at
///                plane.toPlane(x). E.g. SampledReconstruction::fields with planes followed by
///                SampledReconstruction::end_planes.
/// @param params  see LevelSetSmoothingParams.
/// @param keeps   optional: given a candidate voxel solid (one byte per voxel of solid.grid, x
///                fastest, 1 = inside = value < 0), returns true when it keeps the connectivity the
///                caller requires. The result is the last step, of 0..iterations, before the first
///                one `keeps` rejects (checked after every step). Step 0, the input re-distanced
///                (same solid as the input), is not checked: the caller guarantees it.
/// Throws std::invalid_argument when the grid is empty or its voxel size is not positive, when
/// solid.values does not match the grid, when near.size() != planes.size(), or when a parameter is
/// out of range. A solid without boundary (all inside or all outside) comes back as ±band with
/// iterations_applied = 0.
LevelSetSmoothing smoothSolidLevelSet(
    const ScalarField& solid, const std::vector<CuttingPlane>& planes,
    const std::vector<SectionDistanceField>& near, const LevelSetSmoothingParams& params,
    const std::function<bool(const std::vector<std::uint8_t>&)>& keeps = {});

}  // namespace xsect
