// Estimates of α (thesis Def. 26: the angle between a cutting plane and the surface normal at a
// contour point) from neighbouring near-parallel slices, where no other plane's contour crosses:
// between a contour point a of plane P and the nearest contour point b of the nearest
// near-parallel plane Q, the surface is taken to run straight, so its normal is orthogonal to the
// contour's tangent at a and to b − a. An estimate, not a bound (the surface may bend between the
// planes): it is reported to help choose `sampling.max_angle_deg`, never used to decide a verdict.
#pragma once

#include <vector>

#include "geometry/arrangement/section_arrangement.h"
#include "geometry/core/types.h"

namespace xsect {

struct NeighbourAngle {
  int point = -1;          ///< index into the arrangement's points (a contour vertex of plane P)
  int neighbour = -1;      ///< the plane Q
  double alpha_deg = 0;    ///< the estimate at the point
};

struct NeighbourAngleParams {
  double max_plane_angle_deg = 20;  ///< Q within this angle of parallel to P
  std::size_t max_points = 4000;    ///< contour vertices examined (evenly spread)
};

/// @param tolerance_mm  the contours' accuracy, mm: the arc over which tangents are measured and
///                      the distance kept from the border of a plane observed in part.
/// Deterministic; parallel over the points.
std::vector<NeighbourAngle> neighbourAngles(const std::vector<CuttingPlane>& planes, const SectionArrangement& arrangement,
                                            double tolerance_mm, const NeighbourAngleParams& params = {});

}  // namespace xsect
