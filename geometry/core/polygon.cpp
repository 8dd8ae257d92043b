// Planar polygon measures (see polygon.h).
#include "geometry/core/polygon.h"

#include <algorithm>
#include <optional>
#include <cmath>
#include <limits>

namespace xsect {

double signedArea(const Ring& r) {
  double a = 0;
  for (std::size_t i = 0, n = r.size(); i < n; ++i) {
    const Vec2& p = r[i];
    const Vec2& q = r[(i + 1) % n];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

PlaneRect sectionBounds(const std::vector<Section>& sections) {
  PlaneRect r;
  if (sections.empty()) return r;
  Vec2 lo = Vec2::Constant(1e300), hi = -lo;
  for (const auto& s : sections)
    for (const auto& q : s.outer) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  return {lo, hi};
}

Eigen::AlignedBox2d ringBounds(const Ring& ring) {
  Eigen::AlignedBox2d box;  // empty
  for (const Vec2& v : ring) box.extend(v);
  return box;
}

double ringLength(const Ring& r) {
  double l = 0;
  for (std::size_t i = 0, n = r.size(); i < n; ++i) l += (r[(i + 1) % n] - r[i]).norm();
  return l;
}

std::vector<Vec2> contourSamples(const std::vector<Section>& sections, double step) {
  std::vector<Vec2> out;
  const auto ring = [&](const Ring& r) {
    for (std::size_t e = 0; e < r.size(); ++e) {
      const Vec2 a = r[e], b = r[(e + 1) % r.size()];
      const int n = std::isinf(step) ? 1 : std::max(1, int(std::ceil((b - a).norm() / step)));
      for (int q = 0; q < n; ++q) out.push_back(a + (b - a) * (double(q) / n));
    }
  };
  for (const Section& s : sections) {
    ring(s.outer);
    for (const Ring& h : s.holes) ring(h);
  }
  return out;
}

double sectionArea(const Section& s) {
  double a = std::abs(signedArea(s.outer));
  for (const auto& h : s.holes) a -= std::abs(signedArea(h));
  return a;
}

bool ringContains(const Ring& r, const Vec2& p) {
  bool inside = false;
  for (std::size_t i = 0, n = r.size(), j = n - 1; i < n; j = i++) {
    const Vec2& a = r[i];
    const Vec2& b = r[j];
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (p.x() < x) inside = !inside;
    }
  }
  return inside;
}

bool sectionContains(const Section& s, const Vec2& p) {
  if (!ringContains(s.outer, p)) return false;
  for (const auto& h : s.holes)
    if (ringContains(h, p)) return false;
  return true;
}

Vec2 nearestOnSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double l2 = d.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(d) / l2, 0.0, 1.0) : 0.0;
  return a + t * d;
}

bool isSliverTriangle(const Vec2& a, const Vec2& b, const Vec2& c) {
  const Vec2 u = b - a, w = c - a;
  const double area2 = std::abs(u.x() * w.y() - u.y() * w.x());
  return area2 <= 1e-9 * std::max({u.squaredNorm(), w.squaredNorm(), (c - b).squaredNorm()});
}

static double segmentDistance(const Vec2& a, const Vec2& b, const Vec2& p) {
  return (nearestOnSegment(p, a, b) - p).norm();
}

double ringDistance(const Ring& r, const Vec2& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0, n = r.size(); i < n; ++i)
    best = std::min(best, segmentDistance(r[i], r[(i + 1) % n], p));
  return best;
}

double signedDistanceToSections(const std::vector<Section>& sections, const Vec2& p) {
  double d = std::numeric_limits<double>::infinity();
  bool inside = false;
  for (const auto& s : sections) {
    d = std::min(d, ringDistance(s.outer, p));
    for (const auto& h : s.holes) d = std::min(d, ringDistance(h, p));
    inside = inside || sectionContains(s, p);
  }
  return inside ? -d : d;
}

std::vector<Section> sectionsFromRings(std::vector<Ring> outers, std::vector<Ring> holes) {
  std::vector<Section> out(outers.size());
  std::vector<double> area(outers.size());
  for (std::size_t k = 0; k < outers.size(); ++k) {
    Ring& r = outers[k];
    if (signedArea(r) < 0) std::reverse(r.begin(), r.end());
    area[k] = signedArea(r);
    out[k].outer = std::move(r);
  }
  for (auto& h : holes) {
    if (h.empty()) continue;
    if (signedArea(h) > 0) std::reverse(h.begin(), h.end());
    // Tested at a vertex of the hole off the outer ring (a hole may touch its outer ring at a
    // vertex: repaired contours, geometry/core/ring_repair.h).
    int best = -1;
    for (std::size_t k = 0; k < out.size(); ++k) {
      // (every vertex on it: the midpoint of an edge off it, as for a diamond hole on the midpoints
      // of a square's sides.)
      const Ring& o = out[k].outer;
      std::optional<Vec2> off;
      for (std::size_t q = 0; q < h.size() && !off; ++q)
        if (ringDistance(o, h[q]) > 0) off = h[q];
      for (std::size_t q = 0; q < h.size() && !off; ++q) {
        const Vec2 mid = 0.5 * (h[q] + h[(q + 1) % h.size()]);
        if (ringDistance(o, mid) > 0) off = mid;
      }
      if (off && ringContains(o, *off) && (best < 0 || area[k] < area[best])) best = int(k);
    }
    if (best >= 0) out[best].holes.push_back(std::move(h));
  }
  return out;
}

Vec2 sectionCentroid(const Section& s) {
  Vec2 c = Vec2::Zero();
  double a = 0;
  const auto add = [&](const Ring& r, double sign) {
    for (std::size_t i = 0, n = r.size(); i < n; ++i) {
      const Vec2& p = r[i];
      const Vec2& q = r[(i + 1) % n];
      const double w = (p.x() * q.y() - q.x() * p.y()) * sign;
      a += w;
      c += w * (p + q);
    }
  };
  // Orientation-independent: outer counted positive, holes negative.
  add(s.outer, signedArea(s.outer) >= 0 ? 1.0 : -1.0);
  for (const auto& h : s.holes) add(h, signedArea(h) >= 0 ? -1.0 : 1.0);
  if (std::abs(a) < 1e-300) return s.outer.empty() ? Vec2::Zero() : s.outer.front();
  return c / (3.0 * a);
}

}  // namespace xsect
