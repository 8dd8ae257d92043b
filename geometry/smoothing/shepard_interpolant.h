// Shepard's implicit interpolant between the sections (thesis ch. 1 §1.1):
//     f|_C(x) = Σ_i w_i(x) f_i(x_i) / Σ_i w_i(x),   w_i(x) = 1 / g(|x - x_i|),  g(t) = t^p,
// over the planes P_i whose orthogonal projection x_i of x is not cut off by another plane (no
// plane P_j, j ≠ i, crosses the segment [x, x_i]: s_j(x) s_j(x_i) < 0) — the planes of the cell
// C of the arrangement containing x that x sees, as in the thesis' O(k²) procedure. f_i is the
// signed distance to P_i's section-contours, clamped at a cap (plane_distance_function.h).
//
// Limits and conventions:
//  - on a plane (|x - x_i| = 0) f equals the mean of the f_i of the planes through x: f|_{P_i} = f_i
//    (Property 3), so the zero set passes through the section-contours;
//  - p = +inf is method 1: f = f_j(x_j) for the nearest plane P_j (ties: lowest index), which is
//    always visible — method 1's value (nearest_plane_reconstruction.h);
//  - the weights are computed as (t_min / t_i)^p, which is the same ratio without overflow;
//  - the virtual end planes (end_planes.h) take part with their weight scaled by
//    endPlaneWeightFactors; a plane with factor 0 takes no part, even on itself, unless no plane
//    with a positive factor sees x (then f is the nearest plane's value). So as p grows, f tends
//    to the nearest plane with a positive factor, while p = inf is method 1 (the nearest plane).
// f is smooth inside each cell away from the loci where a projection x_i passes behind another
// plane, where the visible set changes and f jumps (a plane that stops being visible is never the
// nearest, so the jump shrinks as p grows).
//
// On observed pieces (issue 20, docs/methods.md, "Observed pieces"; geometry/scene/observed_piece.h) each
// plane P_i is replaced by its piece Ω_i, as methods 1 and 2 do:
//     x_i = the point of Ω_i nearest x (x's projection when Ω_i holds it), t_i = |x - x_i|,
//     P_i sees x when no other piece meets the segment [x, x_i] inside it: no plane P_j, j ≠ i,
//     with s_j(x) s_j(x_i) < 0 whose crossing point lies in Ω_j,
// and f(x) = Σ w_i f_i(x_i) / Σ w_i over the planes that see x, w_i = 1 / g(t_i). An empty piece
// neither sees nor hides. When every piece is whole this is the definition above; the nearest
// piece always sees x (a piece met before x_i would be nearer); on Ω_i, f = f_i (Property 3 where
// the plane was observed).
//
// Speed: the thesis' test is O(k²) per point. Here, as in method 1, boxes of voxels (32³, 8³, 4³,
// 2³) cull the planes. Over a box every plane's signed distance is an exact interval, and whether
// plane q separates x from x_i is the sign of the linear function s_q(x) - (n_q·n_i) s_i(x); a plane
// i is dropped for the whole box when one plane q (not crossing the box) separates it for every x
// of the box, and a plane q is kept as a possible blocker only when it may separate some remaining
// candidate somewhere in the box. Voxels test the survivors (a few planes) exactly. With pieces,
// q drops i only where Ω_i holds the box's projections (then x_i is the projection) and Ω_q holds
// every point where those segments may cross P_q (a disc about the crossing of the box centre's
// segment, of radius ρ / |n_q·n_i|, ρ the box's half-diagonal: the segments run along n_i, so
// their crossings are the box's oblique projection onto P_q); every plane that may cut a segment
// to a piece point is kept as a blocker.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/smoothing/plane_distance_function.h"
#include "geometry/scene/observed_piece.h"
#include "geometry/scene/section_distance_field.h"
#include "geometry/core/types.h"

namespace xsect {

/// The planes and their f_i: planes[i] uses near[i] (band raster) and f[i] (plane_distance_function.h).
struct ShepardData {
  const std::vector<CuttingPlane>* planes = nullptr;
  const std::vector<SectionDistanceField>* near = nullptr;
  const std::vector<PlaneDistanceFunction>* f = nullptr;
  /// Optional factor on each plane's weight w_i (1 when absent): see endPlaneWeightFactors.
  const std::vector<double>* weight_factor = nullptr;
  /// Optional observed piece of each plane (absent: every plane whole, the thesis' definition).
  const std::vector<ObservedPiece>* pieces = nullptr;
};

/// Weight factors for `planes` whose entries from `first_end_plane` on are the virtual end planes
/// (end_planes.h): 1 for a cutting plane; for an end plane E, max over the cutting planes P_i
/// holding sections of (n_i · n_E)².
///
/// Why: the end planes are not cutting planes of the thesis; they close the cells where a
/// section's value would otherwise extend to infinity, which happens along the section's own
/// normal (x_i stays put as x moves along n_i). Along a direction perpendicular to every n_i the
/// projections x_i slide out of the sections and f closes by itself; an end plane facing that way
/// would only add a far "outside" vote, and for p = 1 a plane's vote f_E w_E ≈ (its distance from
/// the surface) / t does not fade with t. A parallel stack thus gets no side end planes in f and,
/// as the thesis states for two parallel planes and g the identity, f between two neighbouring
/// planes is the linear interpolation of their distance functions.
std::vector<double> endPlaneWeightFactors(const std::vector<CuttingPlane>& planes,
                                          std::size_t first_end_plane);

/// The definition, evaluated at x with the thesis' O(k²) visibility test (the reference the fast
/// evaluation is tested against). `exponent` p > 0, +inf allowed. Optionally returns the number
/// of planes that see x.
double shepardValue(const ShepardData& data, const Vec3& x, double exponent, int* visible = nullptr);

struct ShepardField {
  ScalarField value;                  ///< f at the voxel centres (mm), negative inside
  std::int64_t visible_planes = 0;    ///< Σ over voxels of the planes that see the voxel
  int max_visible_planes = 0;         ///< most planes seeing one voxel
};

/// f on every voxel centre of `grid`, with block culling. Deterministic (independent of threads).
/// @param progress  optional, called with the blocks done and the blocks in all (from the calling thread).
ShepardField shepardInterpolant(const ShepardData& data, const GridSpec& grid, double exponent,
                                const std::function<void(std::int64_t, std::int64_t)>& progress = {});

}  // namespace xsect
