// Tangent discs and contour feet on a plane's sections (see tangent_disc.h).
#include "geometry/sampling/tangent_disc.h"

#include <cmath>
#include <limits>

namespace xsect {

namespace {

template <typename Visit>
void forEachRing(const std::vector<Section>& sections, const Visit& visit) {
  for (const Section& s : sections) {
    visit(s.outer);
    for (const Ring& h : s.holes) visit(h);
  }
}

/// The point `arc` mm along the ring from edge e at parameter t (arc < 0: backwards).
Vec2 walk(const Ring& r, std::size_t e, double t, double arc) {
  const std::size_t n = r.size();
  Vec2 p = r[e] + t * (r[(e + 1) % n] - r[e]);
  if (arc >= 0) {
    std::size_t i = (e + 1) % n;
    for (std::size_t step = 0; step < n; ++step, i = (i + 1) % n) {
      const double l = (r[i] - p).norm();
      if (l >= arc) return p + (arc / std::max(l, 1e-300)) * (r[i] - p);
      arc -= l;
      p = r[i];
    }
  } else {
    arc = -arc;
    std::size_t i = e;
    for (std::size_t step = 0; step < n; ++step, i = (i + n - 1) % n) {
      const double l = (r[i] - p).norm();
      if (l >= arc) return p + (arc / std::max(l, 1e-300)) * (r[i] - p);
      arc -= l;
      p = r[i];
    }
  }
  return p;
}

}  // namespace

double tangentDiscRadius(const std::vector<Section>& sections, const Vec2& a, const Vec2& direction,
                         double slack_mm) {
  double best = std::numeric_limits<double>::infinity();
  const double s = std::max(0.0, slack_mm);
  forEachRing(sections, [&](const Ring& r) {
    for (const Vec2& q : r) {
      const Vec2 d = q - a;
      const double along = direction.dot(d);
      if (along <= s) continue;
      best = std::min(best, (d.squaredNorm() - s * s) / (2 * (along - s)));
    }
  });
  return best;
}

ContourFoot nearestContourPoint(const std::vector<Section>& sections, const Vec2& p, double smoothing_mm) {
  ContourFoot f;
  f.distance = std::numeric_limits<double>::infinity();
  const Ring* bestRing = nullptr;
  std::size_t bestEdge = 0;
  double bestT = 0;
  forEachRing(sections, [&](const Ring& r) {
    const std::size_t n = r.size();
    if (n < 2) return;
    for (std::size_t e = 0; e < n; ++e) {
      const Vec2 a = r[e], d = r[(e + 1) % n] - a;
      const double l2 = d.squaredNorm();
      const double t = l2 > 0 ? std::clamp((p - a).dot(d) / l2, 0.0, 1.0) : 0.0;
      const double dist = (a + t * d - p).norm();
      if (dist < f.distance) f.distance = dist, bestRing = &r, bestEdge = e, bestT = t;
    }
  });
  if (!bestRing) return f;
  const Ring& r = *bestRing;
  f.found = true;
  f.point = r[bestEdge] + bestT * (r[(bestEdge + 1) % r.size()] - r[bestEdge]);
  double perimeter = 0;
  for (std::size_t i = 0; i < r.size(); ++i) perimeter += (r[(i + 1) % r.size()] - r[i]).norm();
  const double arc = std::min(smoothing_mm, perimeter / 4);
  const Vec2 chord = walk(r, bestEdge, bestT, arc) - walk(r, bestEdge, bestT, -arc);
  const Vec2 edge = r[(bestEdge + 1) % r.size()] - r[bestEdge];
  const Vec2 t = chord.norm() > 0 ? chord : edge;
  f.tangent = t.norm() > 0 ? Vec2(t / t.norm()) : Vec2(Vec2::UnitX());
  return f;
}

}  // namespace xsect
