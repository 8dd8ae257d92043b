// Upper bounds of the reach from the sections alone (issue 18, "what the data alone can prove";
// thesis ch. 1 Def. 21, 26). If reach(O) ≥ r then at every contour point a the balls of radius r
// tangent to ∂O at a, one inside O and one outside, exist; each meets every cutting plane Q in a
// disc that lies inside Q's sections (the inner ball) or inside their complement (the outer ball).
// The surface normal at a is unknown but for its angle α with the plane of a (it is orthogonal to
// the contour's tangent and its in-plane part points out of the section), so r is refuted at a when
// for every α some plane near a cuts one of the two balls where its sections say otherwise. The
// largest r not refuted bounds the reach at a from above: on a plane alone this is the section's
// tangent disc over cos α, which α near 90° leaves unbounded; neighbouring planes (parallel stacks
// as much as crossing ones) pin α down.
//
// Discretisation is absorbed by a slack σ (the contours' accuracy, the raster's step, and the
// ball's shift between the α sampled): a plane refutes a ball when the ball shrunk by σ holds a
// point of the plane on the wrong side, read from the plane's signed distance raster, or, where the
// raster keeps only the sign (beyond its band), from a contour vertex inside the shrunk ball. The
// contour's in-plane normal is measured from a chord: it is sampled within an error margin too.
// On planes observed only in part (an image, a probe's sector), contour points near the edge of
// what was seen are left out, and their own plane's tangent disc is not used (the border may
// have cut the section).
#pragma once

#include <limits>
#include <vector>

#include "geometry/arrangement/section_arrangement.h"
#include "geometry/core/types.h"
#include "geometry/scene/section_distance_field.h"

namespace xsect {

struct ContourReachBound {
  int point = -1;  ///< index into the arrangement's points (a contour vertex)
  double interior_mm = std::numeric_limits<double>::infinity();  ///< bound of reach_i at it
  double exterior_mm = std::numeric_limits<double>::infinity();  ///< bound of reach_e at it
};

struct ReachBoundParams {
  std::size_t max_points = 1500;  ///< contour vertices examined (evenly spread)
  int neighbour_planes = 6;       ///< planes nearest to the point that test its balls (its own included)
  double alpha_step_deg = 10;     ///< coarsest α step (finer where the ball is large)
  int bisections = 8;             ///< bisection steps after the geometric search for a refuted r
  double normal_error_deg = 4;    ///< how far the contour's measured in-plane normal may be off
};

/// @param planes  all cutting planes (virtual ones are skipped) and their f_P rasters.
/// @param tolerance_mm  the contours' accuracy, mm (part of σ).
/// @param max_reach_mm  radius beyond which nothing is tested (+inf is returned), mm.
/// Deterministic; parallel over the points.
std::vector<ContourReachBound> contourReachBounds(const std::vector<CuttingPlane>& planes,
                                                  const std::vector<SectionDistanceField>& fields,
                                                  const SectionArrangement& arrangement, double tolerance_mm,
                                                  double max_reach_mm, const ReachBoundParams& params = {});

}  // namespace xsect
