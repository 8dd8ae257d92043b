// Traces of sections on the common line of two cutting planes (thesis Introduction §3.1 and
// ch. 2 §5: the sections of two intersecting planes P, Q are assumed to agree on P ∩ Q; this file
// measures whether they do). A trace is the set of intervals of the line that lie in a plane's
// sections; the common region is where both planes were observed (image, field of view).
// Lines are parametrised by arc length t (mm) from a point of the line, so the two planes' traces
// of one line are directly comparable.
#pragma once

#include <optional>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// A closed interval [t0, t1] of a line, mm; t0 < t1, either may be infinite.
struct Interval {
  double t0 = 0, t1 = 0;
  double length() const { return t1 - t0; }
};
/// Sorted, disjoint, non-touching intervals.
using Trace = std::vector<Interval>;

/// The common line of two planes: point(t) = point + t * direction, |direction| = 1.
struct CommonLine {
  Vec3 point = Vec3::Zero();
  Vec3 direction = Vec3::UnitX();
  double angle_deg = 0;  ///< angle between the planes, in (0, 90]
  Vec3 at(double t) const { return point + t * direction; }
};

/// P ∩ Q; none when the planes are parallel (sin of their angle below 1e-9). The point is the one
/// of the line nearest the midpoint of the planes' origins, so t stays moderate for both.
std::optional<CommonLine> commonLine(const Plane& p, const Plane& q);

/// The line in a plane's (u, v) coordinates: o + t d, |d| = 1 (the line lies in the plane).
struct PlaneLine {
  Vec2 o = Vec2::Zero(), d = Vec2::UnitX();
  Vec2 at(double t) const { return o + t * d; }
};
PlaneLine lineInPlane(const Plane& plane, const CommonLine& line);

/// Even-odd inside set of rings along the line: the intervals between successive crossings.
/// Sides are half-open (a vertex is on the left when cross(d, p - o) > 0, else on the right), so
/// every ring crosses an even number of times and a ring touching the line at a vertex gives 0
/// or 2 crossings. Rings of disjoint sections (outers and holes) give the trace of their union.
Trace ringsTrace(const std::vector<const Ring*>& rings, const PlaneLine& line);
/// The trace of a plane's sections on the line.
Trace sectionsTrace(const std::vector<Section>& sections, const PlaneLine& line);
/// Where the plane was observed along the line: its extent rectangle ∩ its field of view, or the
/// whole line (−inf, +inf) when observed_everywhere.
Trace observedTrace(const CuttingPlane& plane, const PlaneLine& line);
/// The extent rectangle's part of it alone (contains observedTrace; cheaper, no field of view).
Trace imageTrace(const CuttingPlane& plane, const PlaneLine& line);

// Interval algebra (results are normalised: sorted, disjoint; pieces shorter than 1e-12 mm drop,
// gaps narrower than 1e-9 mm close: rounding, not geometry).
Trace intersectTraces(const Trace& a, const Trace& b);
Trace uniteTraces(const Trace& a, const Trace& b);
Trace subtractTraces(const Trace& a, const Trace& b);  ///< a \ b
Trace symmetricDifference(const Trace& a, const Trace& b);  ///< (a ∪ b) \ (a ∩ b)
double traceLength(const Trace& a);
/// Length of the longest interval, 0 for an empty trace.
double longestInterval(const Trace& a);

/// How two traces of one line disagree within the common region C.
struct TraceDisagreement {
  double symmetric_difference_mm = 0;  ///< |(A Δ B) ∩ C|
  /// The longest connected piece of (A Δ B) ∩ C: for traces whose intervals correspond one to
  /// one, the largest shift of an endpoint; where an interval has no counterpart, its length.
  double max_endpoint_mismatch_mm = 0;
};
TraceDisagreement traceDisagreement(const Trace& a, const Trace& b, const Trace& common);

/// The average of two traces within C: {t ∈ C : δ_A(t) + δ_B(t) < 0}, δ the signed distance
/// along the line to the trace's endpoints inside C (negative inside; endpoints on C's boundary
/// are where observation stops, not object boundaries, and do not count). Corresponding
/// intervals give the interval of the mean endpoints; an interval without counterpart shrinks
/// by the distance to the other trace's nearest endpoint (or vanishes).
Trace averageTrace(const Trace& a, const Trace& b, const Trace& common);

}  // namespace xsect
