// Where the contours of two crossing planes meet on their common line, the data show the surface
// (thesis ch. 1 §4.5, Def. 26 / ch. 2 Def. 32): both contour tangents lie in the tangent plane of
// ∂O there, so its normal is their cross product, and the angle α_a between a plane and that normal
// is measured. The sections also bound the reach there (issue 18, "what the data alone can prove"):
// the inner medial ball at a, of radius ρ_i(a) ≥ reach_i, meets the plane P_A in a disc of radius
// ρ_i(a)·cos α_a inside the section with a on its circle, so ρ_i(a) ≤ w_i(a) / cos α_a where w_i(a)
// is the largest such disc of the section (tangent_disc.h); the same outside the section for ρ_e.
// Hence reach_i(O_C), reach_e(O_C) and reach_C(O) of a cell whose sections hold a are bounded from
// above by the data alone.
#pragma once

#include <limits>
#include <vector>

#include "geometry/arrangement/section_arrangement.h"
#include "geometry/core/types.h"

namespace xsect {

struct ContourCrossing {
  Vec3 point = Vec3::Zero();    ///< on both planes' contours, mm
  int plane_a = -1, plane_b = -1;
  Vec3 normal = Vec3::Zero();   ///< unit normal of ∂O there (outward)
  double alpha_a_deg = 0, alpha_b_deg = 0;  ///< α at the point for plane a and plane b (Def. 26)
  double alpha_margin_deg = 0;  ///< how far the measured α may be off (CrossingParams)
  /// Upper bounds of the inner and outer medial balls' radii at the point (mm; +inf when the
  /// sections bound nothing on that side): min over both planes of w / cos(α + margin), w the
  /// largest tangent disc over directions within the margin of the measured normal.
  double interior_bound_mm = std::numeric_limits<double>::infinity();
  double exterior_bound_mm = std::numeric_limits<double>::infinity();
};

struct CrossingParams {
  double min_plane_angle_deg = 20;  ///< planes closer to parallel are not used (ill-conditioned)
  double min_tangent_angle_deg = 15;///< contours meeting at a smaller angle are not used
  std::size_t max_crossings = 20000;///< at most this many trace points are examined (evenly spread)
  /// Arc length over which the contours' tangents are measured (a chord), mm. 0: 2 × the planes'
  /// pixel size, at least the crossing tolerance.
  double tangent_arc_mm = 0;
  /// Measurement margins, so that the bounds stay bounds despite the contours' discretisation: the
  /// disc is the largest over directions within this angle of the measured normal, vertices limit
  /// it only beyond twice the crossing tolerance (tangent_disc.h), and α grows by this angle
  /// before dividing by cos α; the angle is divided by the sine of the angle between the two
  /// contour tangents (their errors turn the normal that much more), at most 30°. Contour points
  /// near the border of a plane observed in part are skipped, and such planes give no disc bound.
  double angle_margin_deg = 5;
};

/// @param planes  all cutting planes (virtual planes are skipped: they hold no contour).
/// @param arrangement  its trace points (a contour of one plane crossing another plane) are the
///                candidates; one is kept where the other plane's contour passes within `tolerance_mm`
///                and inside that plane's observed extent.
/// Deterministic (sequential over the candidates kept, parallel within).
std::vector<ContourCrossing> contourCrossings(const std::vector<CuttingPlane>& planes,
                                              const SectionArrangement& arrangement, double tolerance_mm,
                                              const CrossingParams& params = {});

}  // namespace xsect
