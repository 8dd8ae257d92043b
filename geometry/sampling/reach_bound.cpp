// Reach bounds from the sections alone (see reach_bound.h).
#include "geometry/sampling/reach_bound.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "geometry/sampling/contour_vertices.h"
#include "geometry/sampling/observed_edge.h"
#include "geometry/sampling/tangent_disc.h"

namespace xsect {

namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;
constexpr double kInf = std::numeric_limits<double>::infinity();

/// A plane's contour vertices in square buckets, to find one within a distance of a point.
struct VertexBuckets {
  Vec2 origin = Vec2::Zero();
  double size = 1;
  int nu = 0, nv = 0;
  std::vector<int> start;   ///< bucket b holds points[start[b] .. start[b + 1])
  std::vector<Vec2> points;

  explicit VertexBuckets(const std::vector<Section>& sections) {
    std::vector<Vec2> all;
    for (const Section& s : sections) {
      all.insert(all.end(), s.outer.begin(), s.outer.end());
      for (const Ring& h : s.holes) all.insert(all.end(), h.begin(), h.end());
    }
    if (all.empty()) return;
    Vec2 lo = all[0], hi = all[0];
    for (const Vec2& q : all) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
    origin = lo;
    size = std::max((hi - lo).maxCoeff() / 32, 1e-6 * std::max(1.0, hi.cwiseAbs().maxCoeff()));
    nu = int((hi.x() - lo.x()) / size) + 1;
    nv = int((hi.y() - lo.y()) / size) + 1;
    std::vector<int> count(std::size_t(nu) * std::size_t(nv) + 1, 0);
    const auto bucket = [&](const Vec2& q) {
      const int i = std::min(nu - 1, int((q.x() - origin.x()) / size)), j = std::min(nv - 1, int((q.y() - origin.y()) / size));
      return std::size_t(j) * std::size_t(nu) + std::size_t(i);
    };
    for (const Vec2& q : all) ++count[bucket(q) + 1];
    for (std::size_t b = 1; b < count.size(); ++b) count[b] += count[b - 1];
    start = count;
    points.resize(all.size());
    for (const Vec2& q : all) points[std::size_t(count[bucket(q)]++)] = q;
  }

  /// Whether some vertex lies closer than `radius` to p.
  bool anyWithin(const Vec2& p, double radius) const {
    if (points.empty() || radius <= 0) return false;
    const auto cell = [&](double x, int n) { return int(std::clamp(std::floor(x / size), -1.0, double(n))); };
    const int i0 = std::max(0, cell(p.x() - radius - origin.x(), nu)), i1 = std::min(nu - 1, cell(p.x() + radius - origin.x(), nu));
    const int j0 = std::max(0, cell(p.y() - radius - origin.y(), nv)), j1 = std::min(nv - 1, cell(p.y() + radius - origin.y(), nv));
    const double r2 = radius * radius;
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const std::size_t b = std::size_t(j) * std::size_t(nu) + std::size_t(i);
        for (int k = start[b]; k < start[b + 1]; ++k)
          if ((points[std::size_t(k)] - p).squaredNorm() < r2) return true;
      }
    return false;
  }
};

struct Tester {
  const std::vector<CuttingPlane>& planes;
  const std::vector<SectionDistanceField>& fields;
  const std::vector<VertexBuckets>& vertices;
  std::vector<int> near;  ///< planes that test the balls
  Vec3 a = Vec3::Zero(), out = Vec3::Zero(), normal = Vec3::Zero();  ///< point, in-plane outward normal, plane normal
  double slack = 0;
  Vec3 tangent = Vec3::Zero();  ///< the contour's unit tangent at a
  double turn = 0;              ///< how far the measured in-plane normal may be off, radians

  /// Whether plane q refutes a ball (centre c, radius r) that must lie inside O (inner) or outside:
  /// the ball shrunk by the slack s holds a point of the other side on the plane.
  bool refutes(int q, const Vec3& c, double r, bool inner, double s) const {
    const CuttingPlane& Q = planes[std::size_t(q)];
    const double d = Q.plane.signedDistance(c), rs = r - s;
    if (std::abs(d) >= rs) return false;
    const double rho = std::sqrt(r * r - d * d), rhoS = std::sqrt(rs * rs - d * d);
    const Vec2 cq = Q.plane.toPlane(c);
    if (!Q.observed_everywhere) {  // the disc must lie where the plane was observed
      if (!Q.field_of_view.empty()) return false;
      if (!(cq.x() - rho >= Q.extent.min.x() && cq.x() + rho <= Q.extent.max.x() && cq.y() - rho >= Q.extent.min.y() &&
            cq.y() + rho <= Q.extent.max.y()))
        return false;
    }
    const SectionDistanceField& f = fields[std::size_t(q)];
    const double v = f.sample(cq.x(), cq.y());
    const double band = f.band;
    // Where the raster keeps only the sign, a contour vertex within the shrunk disc refutes.
    if (inner) {  // the shrunk disc inside the sections: f(cq) <= -rhoS
      if (v <= -band) return vertices[std::size_t(q)].anyWithin(cq, rhoS);
      return v > -rhoS;
    }
    if (v >= band) return vertices[std::size_t(q)].anyWithin(cq, rhoS);  // outside: f(cq) >= rhoS
    return v < rhoS;
  }

  /// Whether some α leaves a ball of radius r on the `inner` side unrefuted. Its own plane alone
  /// asks r·cos α ≤ w, the section's tangent disc there (`disc`): only |α| ≥ acos(w / r) is
  /// sampled, finely enough that the ball moves by at most about the slack between samples.
  bool feasible(double r, bool inner, double disc, double alphaStep) const {
    const double half = 0.5 * 3.14159265358979323846;
    const double alphaMin = std::acos(std::min(1.0, disc / r));
    const double range = half - alphaMin;
    if (range <= 0) return false;
    double step = std::min(alphaStep, std::max(range / 200, slack / r));
    step = range / std::ceil(range / step);  // samples at the middles of equal steps cover the range
    // The contour's measured normal may be off by up to `turn`: the in-plane direction is sampled
    // at -turn, 0, +turn, and the ball moves by at most r·sin(turn / 2) between them.
    const double s = slack + r * 0.5 * step + r * std::sin(0.5 * turn);
    for (int k = -1; k <= 1; ++k) {
      const Vec3 o = std::cos(k * turn) * out + std::sin(k * turn) * tangent;
      for (double t = alphaMin + 0.5 * step; t < half; t += step)
        for (const double alpha : {t, -t}) {
          const Vec3 n = std::cos(alpha) * o + std::sin(alpha) * normal;
          const Vec3 c = inner ? Vec3(a - r * n) : Vec3(a + r * n);
          bool refuted = false;
          for (int q : near)
            if (refutes(q, c, r, inner, s)) {
              refuted = true;
              break;
            }
          if (!refuted) return true;
        }
    }
    return false;
  }
};

}  // namespace

std::vector<ContourReachBound> contourReachBounds(const std::vector<CuttingPlane>& planes,
                                                  const std::vector<SectionDistanceField>& fields,
                                                  const SectionArrangement& arrangement, double tolerance_mm,
                                                  double max_reach_mm, const ReachBoundParams& params) {
  std::vector<ContourReachBound> out;
  for (const int v : spreadContourVertices(planes, arrangement, params.max_points)) out.push_back({v, kInf, kInf});
  const double alphaStep = params.alpha_step_deg * kDegree;
  std::vector<VertexBuckets> buckets;
  buckets.reserve(planes.size());
  for (const CuttingPlane& p : planes) buckets.emplace_back(p.sections);
  tbb::parallel_for(std::size_t(0), out.size(), [&](std::size_t k) {
    const SectionPoint& s = arrangement.points[std::size_t(out[k].point)];
    const CuttingPlane& P = planes[std::size_t(s.plane)];
    const double step = fields[std::size_t(s.plane)].step;
    // Where the plane was observed only in part, contour points near the edge of what was seen may
    // lie on a cut-off border rather than on the object: they are left out.
    if (nearObservedEdge(P, s.p, std::max(tolerance_mm, 2 * step))) return;
    const ContourFoot foot = nearestContourPoint(P.sections, s.p, std::max(tolerance_mm, 2 * P.pixel_mm));
    if (!foot.found) return;
    Tester t{planes, fields, buckets, {}, P.plane.toWorld(foot.point),
             P.plane.u * foot.tangent.y() - P.plane.v * foot.tangent.x(),  // right of the ring: outward
             P.plane.normal, tolerance_mm + step,
             P.plane.u * foot.tangent.x() + P.plane.v * foot.tangent.y(), params.normal_error_deg * kDegree};
    // The planes nearest to the point (its own first), by distance.
    std::vector<std::pair<double, int>> byDistance;
    for (std::size_t q = 0; q < planes.size(); ++q)
      if (!planes[q].is_virtual) byDistance.push_back({std::abs(planes[q].plane.signedDistance(t.a)), int(q)});
    const std::size_t keep = std::min<std::size_t>(byDistance.size(), std::size_t(std::max(params.neighbour_planes, 1)));
    std::partial_sort(byDistance.begin(), byDistance.begin() + std::ptrdiff_t(keep), byDistance.end());
    for (std::size_t j = 0; j < keep; ++j) t.near.push_back(byDistance[j].second);
    for (int side = 0; side < 2; ++side) {
      const bool inner = side == 0;
      // The own plane's tangent disc (largest over the directions the normal may take) bounds
      // r·cos α; on a plane seen in part, border vertices may cut it short: no bound there.
      const Vec2 in(-foot.tangent.y(), foot.tangent.x());
      double disc = 0;
      if (P.observed_everywhere) {
        for (int d = -1; d <= 1; ++d) {
          const double turn = d * t.turn;
          const Vec2 dir = (inner ? in : Vec2(-in));
          const Vec2 rotated(std::cos(turn) * dir.x() - std::sin(turn) * dir.y(), std::sin(turn) * dir.x() + std::cos(turn) * dir.y());
          disc = std::max(disc, tangentDiscRadius(P.sections, foot.point, rotated, 2 * t.slack));
        }
      } else {
        disc = std::numeric_limits<double>::infinity();
      }
      // Any refuted r bounds the reach (the slack grows with r, so refutation is not monotone in
      // r): radii grow geometrically from the slack until one is refuted, then the gap to the
      // last one standing is bisected, keeping the least refuted radius.
      double lo = 0, hi = 0;
      for (double r = 2 * t.slack; r <= max_reach_mm; r *= 1.5) {
        if (!t.feasible(r, inner, disc, alphaStep)) {
          hi = r;
          break;
        }
        lo = r;
      }
      if (hi == 0) continue;  // nothing refuted below the limit
      for (int b = 0; b < params.bisections; ++b) {
        const double mid = 0.5 * (lo + hi);
        (t.feasible(mid, inner, disc, alphaStep) ? lo : hi) = mid;
      }
      (inner ? out[k].interior_mm : out[k].exterior_mm) = hi;
    }
  });
  return out;
}

}  // namespace xsect
