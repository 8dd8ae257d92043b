// Contour crossings of a common line and their distances to the other plane's contours (see
// contour_piercings.h).
#include "geometry/conformity/contour_piercings.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace xsect {
namespace {

/// The point of `ring` at arc length `arc` from p (on edge k-1 → k) going forward (dir = +1:
/// towards vertex k) or backward; the walk stops after one lap.
Vec2 walk(const Ring& ring, std::size_t k, const Vec2& p, double arc, int dir) {
  const std::size_t n = ring.size();
  Vec2 at = p;
  std::size_t next = dir > 0 ? k : (k + n - 1) % n;
  for (std::size_t steps = 0; steps < n; ++steps) {
    const Vec2 q = ring[next];
    const double len = (q - at).norm();
    if (len >= arc) return at + (q - at) * (len > 0 ? arc / len : 0.0);
    arc -= len;
    at = q;
    next = dir > 0 ? (next + 1) % n : (next + n - 1) % n;
  }
  return at;
}

/// The unit tangent of `ring` at p on edge k-1 → k: the chord over ±arc (the edge for arc 0).
Vec2 tangentAt(const Ring& ring, std::size_t k, const Vec2& p, double arc) {
  const Vec2 edge = ring[k] - ring[k == 0 ? ring.size() - 1 : k - 1];
  Vec2 chord = arc > 0 ? Vec2(walk(ring, k, p, arc, +1) - walk(ring, k, p, arc, -1)) : edge;
  if (chord.norm() == 0) chord = edge;
  return chord.normalized();
}

template <typename F>
void forEachRing(const std::vector<Section>& sections, F f) {
  for (const Section& s : sections) {
    f(s.outer);
    for (const Ring& h : s.holes) f(h);
  }
}

}  // namespace

std::vector<ContourCrossing> contourCrossings(const std::vector<Section>& sections, const PlaneLine& line,
                                              double arc_mm) {
  std::vector<ContourCrossing> out;
  const auto side = [&](const Vec2& p) {
    const Vec2 r = p - line.o;
    return line.d.x() * r.y() - line.d.y() * r.x();
  };
  forEachRing(sections, [&](const Ring& ring) {
    const std::size_t n = ring.size();
    if (n < 3) return;
    double s0 = side(ring[n - 1]);
    for (std::size_t k = 0; k < n; ++k) {
      const Vec2& a = ring[k == 0 ? n - 1 : k - 1];
      const Vec2& b = ring[k];
      const double s1 = side(b);
      if ((s0 > 0) != (s1 > 0)) {  // the half-open rule of ringsTrace
        const Vec2 p = a + (s0 / (s0 - s1)) * (b - a);
        out.push_back({(p - line.o).dot(line.d), tangentAt(ring, k, p, arc_mm)});
      }
      s0 = s1;
    }
  });
  std::sort(out.begin(), out.end(), [](const ContourCrossing& x, const ContourCrossing& y) { return x.t < y.t; });
  return out;
}

bool nearestContourPoint(const std::vector<Section>& sections, const Vec2& p, double arc_mm, Vec2* point,
                         Vec2* tangent) {
  double best = std::numeric_limits<double>::infinity();
  const Ring* bestRing = nullptr;
  std::size_t bestEdge = 0;
  forEachRing(sections, [&](const Ring& ring) {
    const std::size_t n = ring.size();
    if (n < 2) return;
    for (std::size_t k = 0; k < n; ++k) {
      const Vec2& a = ring[k == 0 ? n - 1 : k - 1];
      const Vec2& b = ring[k];
      const Vec2 e = b - a;
      const double len2 = e.squaredNorm();
      const double f = len2 > 0 ? std::clamp((p - a).dot(e) / len2, 0.0, 1.0) : 0.0;
      const Vec2 q = a + f * e;
      const double d = (p - q).squaredNorm();
      if (d < best) {
        best = d;
        *point = q;
        bestRing = &ring;
        bestEdge = k;
      }
    }
  });
  if (!bestRing) return false;
  *tangent = tangentAt(*bestRing, bestEdge, *point, arc_mm);
  return true;
}

double piercingDistance(const ContourPiercing& p) {
  const double s = -p.plane_normal.dot(p.point - p.nearest) / p.plane_normal.dot(p.tangent);
  return (p.point + s * p.tangent - p.nearest).dot(p.contour_normal);
}

std::vector<ContourPiercing> contourPiercings(const std::vector<CuttingPlane>& planes,
                                              const std::vector<PlanePairTraces>& pairs,
                                              const PiercingParams& params) {
  const double minSin = std::sin(params.min_crossing_deg * M_PI / 180.0);
  std::vector<std::vector<ContourPiercing>> perPair(pairs.size());
  tbb::parallel_for(std::size_t(0), pairs.size(), [&](std::size_t k) {
    const PlanePairTraces& pp = pairs[k];
    for (const auto& [from, to] : {std::pair{pp.a, pp.b}, std::pair{pp.b, pp.a}}) {
      const CuttingPlane &pf = planes[std::size_t(from)], &pt = planes[std::size_t(to)];
      const PlaneLine lf = lineInPlane(pf.plane, pp.line), lt = lineInPlane(pt.plane, pp.line);
      for (const ContourCrossing& c : contourCrossings(pf.sections, lf, params.arc_mm)) {
        const bool observed = std::any_of(pp.common.begin(), pp.common.end(),
                                          [&](const Interval& i) { return c.t > i.t0 && c.t < i.t1; });
        if (!observed) continue;
        ContourPiercing p;
        p.from = from;
        p.to = to;
        p.point = pf.plane.toWorld(lf.at(c.t));
        p.tangent = (c.tangent.x() * pf.plane.u + c.tangent.y() * pf.plane.v).normalized();
        if (p.tangent.cross(pp.line.direction).norm() < minSin) continue;
        Vec2 q, tq;
        if (!nearestContourPoint(pt.sections, lt.at(c.t), params.arc_mm, &q, &tq)) continue;
        if ((q - lt.at(c.t)).norm() > params.gate_mm) continue;
        // Too oblique to plane `to` (nearly parallel pairs) to follow the contour into it.
        if (std::abs(pt.plane.normal.dot(p.tangent)) < 0.02) continue;
        p.nearest = pt.plane.toWorld(q);
        const Vec3 tangentTo = tq.x() * pt.plane.u + tq.y() * pt.plane.v;
        if (!(tangentTo.norm() > 0)) continue;
        p.plane_normal = pt.plane.normal;
        p.contour_normal = pt.plane.normal.cross(tangentTo).normalized();
        perPair[k].push_back(p);
      }
    }
  });
  std::vector<ContourPiercing> out;
  for (auto& v : perPair) out.insert(out.end(), v.begin(), v.end());
  return out;
}

}  // namespace xsect
