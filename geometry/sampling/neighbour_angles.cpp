// α estimated from neighbouring near-parallel slices (see neighbour_angles.h).
#include "geometry/sampling/neighbour_angles.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>

#include "geometry/sampling/contour_vertices.h"
#include "geometry/sampling/observed_edge.h"
#include "geometry/sampling/tangent_disc.h"

namespace xsect {

std::vector<NeighbourAngle> neighbourAngles(const std::vector<CuttingPlane>& planes, const SectionArrangement& arrangement,
                                            double tolerance_mm, const NeighbourAngleParams& params) {
  constexpr double kDegree = 3.14159265358979323846 / 180.0;
  std::vector<NeighbourAngle> out;
  for (const int v : spreadContourVertices(planes, arrangement, params.max_points)) out.push_back({v, -1, 0});
  const double cosMax = std::cos(params.max_plane_angle_deg * kDegree);
  tbb::parallel_for(std::size_t(0), out.size(), [&](std::size_t k) {
    const SectionPoint& s = arrangement.points[std::size_t(out[k].point)];
    const CuttingPlane& P = planes[std::size_t(s.plane)];
    const double arc = std::max(2 * P.pixel_mm, tolerance_mm);  // no fixed length: any units
    if (nearObservedEdge(P, s.p, arc)) return;
    const Vec3 a = P.plane.toWorld(s.p);
    // The nearest near-parallel plane holding sections, by distance from a.
    int best = -1;
    double bestDistance = std::numeric_limits<double>::infinity();
    for (std::size_t q = 0; q < planes.size(); ++q) {
      const CuttingPlane& Q = planes[q];
      if (int(q) == s.plane || Q.is_virtual || Q.sections.empty()) continue;
      if (std::abs(Q.plane.normal.dot(P.plane.normal)) < cosMax) continue;
      const double d = std::abs(Q.plane.signedDistance(a));
      if (d > 1e-9 && d < bestDistance) bestDistance = d, best = int(q);
    }
    if (best < 0) return;
    const CuttingPlane& Q = planes[std::size_t(best)];
    const Vec2 aq = Q.plane.toPlane(a);
    if (nearObservedEdge(Q, aq, arc)) return;
    const ContourFoot fb = nearestContourPoint(Q.sections, aq, arc);
    const ContourFoot fa = nearestContourPoint(P.sections, s.p, arc);
    if (!fb.found || !fa.found || nearObservedEdge(Q, fb.point, arc)) return;
    const Vec3 t = P.plane.u * fa.tangent.x() + P.plane.v * fa.tangent.y();
    const Vec3 n = t.cross(Q.plane.toWorld(fb.point) - a);
    if (n.norm() < 1e-12) return;
    out[k].neighbour = best;
    out[k].alpha_deg = std::asin(std::min(1.0, std::abs(n.normalized().dot(P.plane.normal)))) / kDegree;
  });
  std::vector<NeighbourAngle> kept;
  for (const NeighbourAngle& e : out)
    if (e.neighbour >= 0) kept.push_back(e);
  return kept;
}

}  // namespace xsect
