// The largest disc inside (or outside) the sections of a plane with a given contour point on its
// circle, its centre along a given direction (thesis ch. 1 Def. 26: the trace of a medial ball on a
// cutting plane; issue 18). Contours carry discretisation noise, so a vertex only limits the disc
// when it enters it deeper than a slack σ: the disc centred at a + t·d of radius t holds q deeper
// than σ (|a + t·d − q| < t − σ) exactly when
//     t > (|q − a|² − σ²) / (2 (d·(q − a) − σ))     (d·(q − a) > σ),
// so the radius is the least such bound over the vertices of every contour of the plane (outer
// rings and holes alike). A true tangent disc whose contour the vertices follow within σ/2 (a
// included) passes, so the radius bounds it from above.
#pragma once

#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// @param sections  the plane's sections (plane coordinates, mm).
/// @param a         a point on one of their contours, plane coordinates.
/// @param direction unit direction of the centre from a (into the section for the inner disc).
/// @param slack_mm  σ, mm (≥ 0).
/// @returns the radius, mm; +inf when no vertex limits it.
double tangentDiscRadius(const std::vector<Section>& sections, const Vec2& a, const Vec2& direction,
                         double slack_mm);

/// The point of the sections' contours nearest to p, with the contour's unit tangent there
/// (the chord between the contour points `smoothing_mm` of arc before and after it).
struct ContourFoot {
  double distance = 0;
  Vec2 point = Vec2::Zero(), tangent = Vec2::UnitX();
  bool found = false;
};
ContourFoot nearestContourPoint(const std::vector<Section>& sections, const Vec2& p, double smoothing_mm);

}  // namespace xsect
