// Where one slice's contours pierce another slice's plane, and how far from that slice's contours:
// the observations from which pose correction estimates each slice's tracking error
// (geometry/conformity/pose_correction.h). Thesis Introduction §3.1 assumes that the sections of
// two intersecting planes P, Q agree on P ∩ Q: then every point where a contour of P crosses the
// common line lies on a contour of Q. With wrong poses it lies off them; its distance, in Q, to
// the nearest contour of Q is the observation (signed along that contour's normal). Unlike a
// matching of the two traces' endpoints, it needs no correspondence: a section that one slice
// sees on the line and the other does not (a near-tangent cut) still tells how far off it is.
#pragma once

#include <vector>

#include "geometry/arrangement/plane_pair_traces.h"
#include "geometry/core/types.h"

namespace xsect {

/// A contour's crossing of a line in its plane.
struct ContourCrossing {
  double t = 0;                  ///< along the line, mm
  Vec2 tangent = Vec2::UnitX();  ///< the contour's unit tangent there, plane coordinates
};

/// Every crossing of the sections' rings with the line, sorted by t (the endpoints of
/// sectionsTrace, with the same half-open rule at vertices). The tangent is the chord between the
/// ring's points arc_mm before and after the crossing (the crossed edge when arc_mm = 0): over a
/// few pixels it averages the staircase of a segmented contour.
std::vector<ContourCrossing> contourCrossings(const std::vector<Section>& sections, const PlaneLine& line,
                                              double arc_mm);

/// The nearest point of the sections' rings to p (plane coordinates) and the rings' unit tangent
/// there (chord over ±arc_mm); false when there are no rings.
bool nearestContourPoint(const std::vector<Section>& sections, const Vec2& p, double arc_mm, Vec2* point,
                         Vec2* tangent);

/// A contour of plane `from` piercing plane `to`, with the nearest contour point of `to` (world).
struct ContourPiercing {
  int from = -1, to = -1;        ///< plane indices
  Vec3 point = Vec3::Zero();     ///< where the contour of `from` crosses the common line
  Vec3 tangent = Vec3::UnitX();  ///< that contour's unit tangent there
  Vec3 nearest = Vec3::Zero();   ///< the nearest point of a contour of `to`
  Vec3 contour_normal = Vec3::UnitY();  ///< unit normal of that contour, in the plane `to`
  Vec3 plane_normal = Vec3::UnitZ();    ///< the normal of plane `to`
};

/// The signed distance (mm), in plane `to`, from the piercing point to the tangent line of `to`'s
/// contour at the nearest point: the observation's residual.
double piercingDistance(const ContourPiercing& p);

struct PiercingParams {
  double gate_mm = 1.0;   ///< piercings farther than this from every contour of `to` are left out
  double arc_mm = 0.0;    ///< tangent chord half-length
  /// Crossings where the contour runs within this angle of the line (degrees) are left out: it
  /// pierces the other plane too obliquely for its point to be well defined.
  double min_crossing_deg = 10.0;
};

/// Both directions of every pair (a's contours in b, then b's in a), restricted to where both planes
/// were observed (strictly inside `common`). In pair order, crossings along each line in order.
/// Parallel over the pairs; deterministic.
std::vector<ContourPiercing> contourPiercings(const std::vector<CuttingPlane>& planes,
                                              const std::vector<PlanePairTraces>& pairs,
                                              const PiercingParams& params);

}  // namespace xsect
