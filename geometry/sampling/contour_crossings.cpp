// Surface normals, angles α and reach bounds where two planes' contours meet (contour_crossings.h).
#include "geometry/sampling/contour_crossings.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <optional>

#include "geometry/sampling/observed_edge.h"
#include "geometry/sampling/tangent_disc.h"

namespace xsect {

namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

Vec3 inWorld(const Plane& p, const Vec2& d) { return p.u * d.x() + p.v * d.y(); }

}  // namespace

std::vector<ContourCrossing> contourCrossings(const std::vector<CuttingPlane>& planes,
                                              const SectionArrangement& arrangement, double tolerance_mm,
                                              const CrossingParams& params) {
  std::vector<const SectionPoint*> candidates;
  for (const SectionPoint& s : arrangement.points) {
    if (s.kind != SectionPoint::trace || s.trace_plane < 0) continue;
    const CuttingPlane& A = planes[std::size_t(s.plane)];
    const CuttingPlane& B = planes[std::size_t(s.trace_plane)];
    if (A.is_virtual || B.is_virtual || B.sections.empty()) continue;
    if (std::abs(A.plane.normal.dot(B.plane.normal)) > std::cos(params.min_plane_angle_deg * kDegree)) continue;
    candidates.push_back(&s);
  }
  const std::size_t stride =
      params.max_crossings > 0 ? std::max<std::size_t>(1, (candidates.size() + params.max_crossings - 1) / params.max_crossings) : 1;
  std::vector<const SectionPoint*> kept;
  for (std::size_t i = 0; i < candidates.size(); i += stride) kept.push_back(candidates[i]);

  std::vector<std::optional<ContourCrossing>> found(kept.size());
  const double sinTangent = std::sin(params.min_tangent_angle_deg * kDegree);
  tbb::parallel_for(std::size_t(0), kept.size(), [&](std::size_t i) {
    const SectionPoint& s = *kept[i];
    const CuttingPlane& A = planes[std::size_t(s.plane)];
    const CuttingPlane& B = planes[std::size_t(s.trace_plane)];
    const Vec3 x = A.plane.toWorld(s.p);
    const Vec2 pB = B.plane.toPlane(x);
    // Contours along the border of what a plane observed are not the object's surface.
    if (nearObservedEdge(A, s.p, tolerance_mm) || nearObservedEdge(B, pB, tolerance_mm)) return;
    const double arc = params.tangent_arc_mm > 0 ? params.tangent_arc_mm
                                                 : std::max({2 * A.pixel_mm, 2 * B.pixel_mm, tolerance_mm});
    const ContourFoot fB = nearestContourPoint(B.sections, pB, arc);
    if (!fB.found || fB.distance > tolerance_mm) return;
    const ContourFoot fA = nearestContourPoint(A.sections, s.p, arc);
    if (!fA.found) return;
    const Vec3 tA = inWorld(A.plane, fA.tangent), tB = inWorld(B.plane, fB.tangent);
    Vec3 n = tA.cross(tB);
    const double sinCrossing = n.norm();
    if (sinCrossing < sinTangent) return;
    n.normalize();
    // Tangent errors turn the normal by up to 1/sin(crossing angle) times as much.
    const double margin = std::min(30.0, params.angle_margin_deg / sinCrossing);
    // The sections lie to the left of their rings' direction (outer rings counter-clockwise, holes
    // clockwise): inward in-plane normals.
    const Vec2 inA(-fA.tangent.y(), fA.tangent.x()), inB(-fB.tangent.y(), fB.tangent.x());
    if (n.dot(inWorld(A.plane, inA)) > 0) n = -n;       // outward
    if (n.dot(inWorld(B.plane, inB)) > 0) return;         // the two contours disagree on the side
    ContourCrossing c;
    c.point = x;
    c.plane_a = s.plane;
    c.plane_b = s.trace_plane;
    c.normal = n;
    const double sa = std::min(1.0, std::abs(n.dot(A.plane.normal))), sb = std::min(1.0, std::abs(n.dot(B.plane.normal)));
    c.alpha_a_deg = std::asin(sa) / kDegree;
    c.alpha_b_deg = std::asin(sb) / kDegree;
    c.alpha_margin_deg = margin;
    const auto widened = [&](double alpha_deg) { return std::cos(std::min(90.0, alpha_deg + margin) * kDegree); };
    const double ca = widened(c.alpha_a_deg), cb = widened(c.alpha_b_deg);
    // The largest disc over directions within the angle margin of the measured normal: the true
    // normal lies among them when the contour's tangent is within the margin.
    const auto bound = [&](const CuttingPlane& P, const Vec2& at, const Vec2& dir, double cosine) {
      // On a plane seen in part, border vertices may cut the disc short: no bound from it.
      if (!P.observed_everywhere) return std::numeric_limits<double>::infinity();
      const std::vector<Section>& secs = P.sections;
      double w = 0;
      for (int k = -2; k <= 2; ++k) {
        const double t = 0.5 * k * margin * kDegree;
        const Vec2 d(std::cos(t) * dir.x() - std::sin(t) * dir.y(), std::sin(t) * dir.x() + std::cos(t) * dir.y());
        w = std::max(w, tangentDiscRadius(secs, at, d, 2 * tolerance_mm));
      }
      return cosine > 1e-6 ? w / cosine : std::numeric_limits<double>::infinity();
    };
    c.interior_bound_mm = std::min(bound(A, fA.point, inA, ca), bound(B, fB.point, inB, cb));
    c.exterior_bound_mm = std::min(bound(A, fA.point, -inA, ca), bound(B, fB.point, -inB, cb));
    found[i] = c;
  });
  std::vector<ContourCrossing> out;
  for (auto& f : found)
    if (f) out.push_back(*f);
  return out;
}

}  // namespace xsect
