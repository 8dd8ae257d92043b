// Traces of sections on common lines, and interval algebra (see section_traces.h).
#include "geometry/arrangement/section_traces.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace xsect {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kShortest = 1e-12;  // mm: shorter pieces are rounding, not geometry
constexpr double kNarrowestGap = 1e-9;  // mm: narrower gaps are rounding (e.g. two edits meeting)

Trace normalised(Trace t) {
  std::sort(t.begin(), t.end(), [](const Interval& x, const Interval& y) {
    return x.t0 < y.t0 || (x.t0 == y.t0 && x.t1 < y.t1);
  });
  Trace out;
  for (const Interval& i : t) {
    if (!(i.t1 - i.t0 > kShortest)) continue;
    if (!out.empty() && i.t0 <= out.back().t1 + kNarrowestGap)
      out.back().t1 = std::max(out.back().t1, i.t1);
    else
      out.push_back(i);
  }
  return out;
}

/// Signed distance along the line from t to the boundary of X, counting only the endpoints in
/// `ends` (negative inside X); ±1e12 when there is none.
double alongDistance(const Trace& x, const std::vector<double>& ends, double t) {
  bool inside = false;
  for (const Interval& i : x) inside = inside || (i.t0 <= t && t <= i.t1);
  double d = 1e12;
  const auto it = std::lower_bound(ends.begin(), ends.end(), t);
  if (it != ends.end()) d = std::min(d, *it - t);
  if (it != ends.begin()) d = std::min(d, t - *(it - 1));
  return inside ? -d : d;
}

/// Endpoints of x strictly inside the interval c.
std::vector<double> endsWithin(const Trace& x, const Interval& c) {
  std::vector<double> e;
  for (const Interval& i : x)
    for (const double t : {i.t0, i.t1})
      if (t > c.t0 && t < c.t1 && std::isfinite(t)) e.push_back(t);
  return e;
}

}  // namespace

std::optional<CommonLine> commonLine(const Plane& p, const Plane& q) {
  const Vec3 n = p.normal.cross(q.normal);
  const double s = n.norm();
  if (!(s >= 1e-9)) return std::nullopt;
  CommonLine L;
  L.direction = n / s;
  L.angle_deg = std::asin(std::min(1.0, s)) * 180.0 / M_PI;
  const Vec3 m = 0.5 * (p.origin + q.origin);
  const double c = p.normal.dot(q.normal);
  const double rp = p.normal.dot(p.origin - m), rq = q.normal.dot(q.origin - m);
  const double det = 1.0 - c * c;
  const double alpha = (rp - c * rq) / det, beta = (rq - c * rp) / det;
  L.point = m + alpha * p.normal + beta * q.normal;
  return L;
}

PlaneLine lineInPlane(const Plane& plane, const CommonLine& line) {
  PlaneLine l;
  l.o = plane.toPlane(line.point);
  const Vec2 d(line.direction.dot(plane.u), line.direction.dot(plane.v));
  l.d = d / d.norm();
  return l;
}

Trace ringsTrace(const std::vector<const Ring*>& rings, const PlaneLine& line) {
  std::vector<double> crossings;
  for (const Ring* ring : rings) {
    const std::size_t n = ring->size();
    if (n < 3) continue;
    const auto side = [&](const Vec2& p) {
      const Vec2 r = p - line.o;
      return line.d.x() * r.y() - line.d.y() * r.x();
    };
    double s0 = side((*ring)[n - 1]);
    for (std::size_t k = 0; k < n; ++k) {
      const Vec2& a = (*ring)[k == 0 ? n - 1 : k - 1];
      const Vec2& b = (*ring)[k];
      const double s1 = side(b);
      if ((s0 > 0) != (s1 > 0)) {
        const double ta = (a - line.o).dot(line.d), tb = (b - line.o).dot(line.d);
        crossings.push_back(ta + (tb - ta) * (s0 / (s0 - s1)));
      }
      s0 = s1;
    }
  }
  std::sort(crossings.begin(), crossings.end());
  Trace t;
  for (std::size_t k = 0; k + 1 < crossings.size(); k += 2) t.push_back({crossings[k], crossings[k + 1]});
  return normalised(std::move(t));
}

Trace sectionsTrace(const std::vector<Section>& sections, const PlaneLine& line) {
  std::vector<const Ring*> rings;
  for (const Section& s : sections) {
    rings.push_back(&s.outer);
    for (const Ring& h : s.holes) rings.push_back(&h);
  }
  return ringsTrace(rings, line);
}

Trace imageTrace(const CuttingPlane& plane, const PlaneLine& line) {
  if (plane.observed_everywhere) return {{-kInf, kInf}};
  // The extent rectangle (Liang-Barsky).
  double lo = -kInf, hi = kInf;
  for (int axis = 0; axis < 2; ++axis) {
    const double o = line.o[axis], d = line.d[axis];
    const double mn = plane.extent.min[axis], mx = plane.extent.max[axis];
    if (std::abs(d) < 1e-15) {
      if (o < mn || o > mx) return {};
      continue;
    }
    double a = (mn - o) / d, b = (mx - o) / d;
    if (a > b) std::swap(a, b);
    lo = std::max(lo, a);
    hi = std::min(hi, b);
  }
  return normalised({{lo, hi}});
}

Trace observedTrace(const CuttingPlane& plane, const PlaneLine& line) {
  const Trace rect = imageTrace(plane, line);
  if (plane.observed_everywhere || rect.empty() || plane.field_of_view.empty()) return rect;
  std::vector<const Ring*> rings;
  for (const Ring& r : plane.field_of_view) rings.push_back(&r);
  return intersectTraces(rect, ringsTrace(rings, line));
}

Trace intersectTraces(const Trace& a, const Trace& b) {
  Trace out;
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const double lo = std::max(a[i].t0, b[j].t0), hi = std::min(a[i].t1, b[j].t1);
    if (hi > lo) out.push_back({lo, hi});
    (a[i].t1 < b[j].t1) ? ++i : ++j;
  }
  return normalised(std::move(out));
}

Trace uniteTraces(const Trace& a, const Trace& b) {
  Trace all = a;
  all.insert(all.end(), b.begin(), b.end());
  return normalised(std::move(all));
}

Trace subtractTraces(const Trace& a, const Trace& b) {
  Trace out;
  for (Interval i : a) {
    for (const Interval& r : b) {
      if (r.t1 <= i.t0 || r.t0 >= i.t1) continue;
      if (r.t0 > i.t0) out.push_back({i.t0, r.t0});
      i.t0 = std::max(i.t0, r.t1);
      if (i.t0 >= i.t1) break;
    }
    if (i.t1 > i.t0) out.push_back(i);
  }
  return normalised(std::move(out));
}

Trace symmetricDifference(const Trace& a, const Trace& b) {
  return subtractTraces(uniteTraces(a, b), intersectTraces(a, b));
}

double traceLength(const Trace& a) {
  double l = 0;
  for (const Interval& i : a) l += i.length();
  return l;
}

double longestInterval(const Trace& a) {
  double l = 0;
  for (const Interval& i : a) l = std::max(l, i.length());
  return l;
}

TraceDisagreement traceDisagreement(const Trace& a, const Trace& b, const Trace& common) {
  const Trace diff = intersectTraces(symmetricDifference(a, b), common);
  return {traceLength(diff), longestInterval(diff)};
}

Trace averageTrace(const Trace& a, const Trace& b, const Trace& common) {
  Trace out;
  for (const Interval& c : common) {
    const std::vector<double> ea = endsWithin(a, c), eb = endsWithin(b, c);
    // Breakpoints of δ_A + δ_B: the endpoints and the midpoints between successive endpoints of
    // each trace; the sum is linear between successive breakpoints.
    std::vector<double> bp = ea;
    bp.insert(bp.end(), eb.begin(), eb.end());
    for (const auto* e : {&ea, &eb})
      for (std::size_t k = 0; k + 1 < e->size(); ++k) bp.push_back(0.5 * ((*e)[k] + (*e)[k + 1]));
    double lo = c.t0, hi = c.t1;
    if (!bp.empty()) {
      const double first = *std::min_element(bp.begin(), bp.end());
      const double last = *std::max_element(bp.begin(), bp.end());
      if (!std::isfinite(lo)) lo = first - 1.0;
      if (!std::isfinite(hi)) hi = last + 1.0;
    } else if (!std::isfinite(lo) || !std::isfinite(hi)) {
      // no endpoint at all: both traces are constant on an unbounded C; sections are bounded,
      // so both are empty here
      continue;
    }
    bp.push_back(lo);
    bp.push_back(hi);
    std::sort(bp.begin(), bp.end());
    bp.erase(std::unique(bp.begin(), bp.end()), bp.end());
    const auto sum = [&](double t) { return alongDistance(a, ea, t) + alongDistance(b, eb, t); };
    double t0 = bp[0], v0 = sum(t0);
    for (std::size_t k = 1; k < bp.size(); ++k) {
      const double t1 = bp[k], v1 = sum(t1);
      if (v0 < 0 && v1 < 0) {
        out.push_back({t0, t1});
      } else if (v0 < 0) {
        out.push_back({t0, t0 + (t1 - t0) * (v0 / (v0 - v1))});
      } else if (v1 < 0) {
        out.push_back({t0 + (t1 - t0) * (v0 / (v0 - v1)), t1});
      }
      t0 = t1;
      v0 = v1;
    }
  }
  return normalised(std::move(out));
}

}  // namespace xsect
