// The largest disc inside (or outside) the sections of a plane with a given contour point on its
// circle, its centre along a given direction (thesis ch. 1 Def. 26: the trace of a medial ball on a
// cutting plane; issue 18). A disc centred at a + t·d through a meets a contour vertex q first at
//     t(q) = |q − a|² / (2 d·(q − a))     (d·(q − a) > 0),
// so the radius is the least t(q) over the vertices of every contour of the plane (outer rings and
// holes alike). Vertices nearer than `exclude_mm` to a are skipped (the polygon's own corners next
// to a), which can only make the radius larger: callers use it as an upper bound of a medial ball.
#pragma once

#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// @param sections  the plane's sections (plane coordinates, mm).
/// @param a         a point on one of their contours, plane coordinates.
/// @param direction unit direction of the centre from a (into the section for the inner disc).
/// @returns the radius, mm; +inf when no vertex limits it.
double tangentDiscRadius(const std::vector<Section>& sections, const Vec2& a, const Vec2& direction,
                         double exclude_mm);

/// The point of the sections' contours nearest to p, with the contour's unit tangent there
/// (the chord between the contour points `smoothing_mm` of arc before and after it).
struct ContourFoot {
  double distance = 0;
  Vec2 point = Vec2::Zero(), tangent = Vec2::UnitX();
  bool found = false;
};
ContourFoot nearestContourPoint(const std::vector<Section>& sections, const Vec2& p, double smoothing_mm);

}  // namespace xsect
