// Consensus traces and local, exact edits of the sections (see conformity_enforcement.h).
// CGAL's Boolean operations on polygons with holes (exact constructions) live only here.
#include "geometry/conformity/conformity_enforcement.h"

#include <tbb/parallel_for.h>

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_set_2.h>
#include <CGAL/Polygon_with_holes_2.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "geometry/core/polygon.h"

namespace xsect {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = K::Point_2;
using Polygon = CGAL::Polygon_2<K>;
using PolygonWithHoles = CGAL::Polygon_with_holes_2<K>;
using PolygonSet = CGAL::Polygon_set_2<K>;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kSame = 1e-12;  // mm: endpoints this close are the same endpoint

/// One line's edit of one plane: its current trace O, the consensus T, the common region C.
struct LineEdit {
  CommonLine line;
  Trace current, consensus, common;
};

/// A rhombus on the line: diagonal [s0, s1] along it, half-width w across it.
struct Rhombus {
  double s0, s1, w;
};

/// The interval of `t` that ends (side 0: starts) at x, if any.
const Interval* touching(const Trace& t, double x, bool endsAtX) {
  for (const Interval& i : t)
    if (std::abs((endsAtX ? i.t1 : i.t0) - x) <= kSame) return &i;
  return nullptr;
}

/// Length of the gap of `t` that begins (after=true) or ends at x: the distance to the next
/// interval on that side, +inf when there is none.
double gapBeside(const Trace& t, double x, bool after) {
  double g = kInf;
  for (const Interval& i : t) {
    if (after && i.t0 > x + kSame) g = std::min(g, i.t0 - x);
    if (!after && i.t1 < x - kSame) g = std::min(g, x - i.t1);
  }
  return g;
}

/// The rhombi that turn trace O into T along one line (T ⊆ C; outside C nothing changes).
/// Added pieces are extended into the interval of O they continue, removed pieces into the gap of
/// O beyond the section's boundary, by at most a quarter of that interval or gap and the piece's
/// own length, so that a rhombus tip never lies on the section's boundary.
void rhombiOfLine(const LineEdit& e, double band, std::vector<Rhombus>* add,
                  std::vector<Rhombus>* remove) {
  const auto rhombus = [&](double s0, double s1) {
    return Rhombus{s0, s1, std::min(band, 0.5 * (s1 - s0))};
  };
  for (const Interval& a : subtractTraces(e.consensus, e.current)) {
    const double len = a.length();
    double e0 = 0, e1 = 0;
    if (const Interval* o = touching(e.current, a.t0, true)) e0 = std::min(len, 0.25 * o->length());
    if (const Interval* o = touching(e.current, a.t1, false)) e1 = std::min(len, 0.25 * o->length());
    add->push_back(rhombus(a.t0 - e0, a.t1 + e1));
  }
  const Trace inC = intersectTraces(e.current, e.common);
  for (const Interval& d : subtractTraces(inC, e.consensus)) {
    const double len = d.length();
    double e0 = 0, e1 = 0;
    if (touching(e.current, d.t0, false)) e0 = std::min(len, 0.25 * gapBeside(e.current, d.t0, false));
    if (touching(e.current, d.t1, true)) e1 = std::min(len, 0.25 * gapBeside(e.current, d.t1, true));
    remove->push_back(rhombus(d.t0 - e0, d.t1 + e1));
  }
}

Ring withoutRepeats(const Ring& r) {
  Ring out;
  for (const Vec2& p : r)
    if (out.empty() || p != out.back()) out.push_back(p);
  while (out.size() > 1 && out.front() == out.back()) out.pop_back();
  return out;
}

Polygon toPolygon(const Ring& r) {
  Polygon p;
  for (const Vec2& v : r) p.push_back(Point(v.x(), v.y()));
  return p;
}

Ring toRing(const Polygon& p) {
  Ring r;
  for (auto v = p.vertices_begin(); v != p.vertices_end(); ++v)
    r.emplace_back(CGAL::to_double(v->x()), CGAL::to_double(v->y()));
  return withoutRepeats(r);
}

/// The section as a CGAL polygon with holes; false when a ring is not simple.
bool toPolygonWithHoles(const Section& s, PolygonWithHoles* out) {
  Polygon outer = toPolygon(withoutRepeats(s.outer));
  if (outer.size() < 3 || !outer.is_simple()) return false;
  if (outer.orientation() != CGAL::COUNTERCLOCKWISE) outer.reverse_orientation();
  std::vector<Polygon> holes;
  for (const Ring& h : s.holes) {
    Polygon p = toPolygon(withoutRepeats(h));
    if (p.size() < 3) continue;
    if (!p.is_simple()) return false;
    if (p.orientation() != CGAL::CLOCKWISE) p.reverse_orientation();
    holes.push_back(std::move(p));
  }
  *out = PolygonWithHoles(outer, holes.begin(), holes.end());
  return true;
}

/// Lexicographically smallest vertex: a canonical order for edited sections.
Vec2 smallestVertex(const Ring& r) {
  Vec2 m = r.front();
  for (const Vec2& p : r)
    if (p.x() < m.x() || (p.x() == m.x() && p.y() < m.y())) m = p;
  return m;
}

struct PlaneEditResult {
  std::vector<Section> sections;
  bool changed = false, editable = true;
  int added = 0, removed = 0, bumps = 0;
  double max_half_width = 0;
};

Polygon triangle(const Vec2& a, const Vec2& b, const Vec2& c) {
  Polygon p;
  for (const Vec2& v : {a, b, c}) p.push_back(Point(v.x(), v.y()));
  if (p.orientation() != CGAL::COUNTERCLOCKWISE) p.reverse_orientation();
  return p;
}

double distanceToLine(const Vec2& p, const PlaneLine& l) {
  const Vec2 q = p - l.o;
  return std::abs(l.d.x() * q.y() - l.d.y() * q.x());
}

/// A line of the plane with the trace it must end with (its consensus where it is being
/// enforced, its current trace otherwise).
struct GuardedLine {
  PlaneLine line;
  Trace target;
};

/// The piece of `line` inside a convex polygon (counter-clockwise), empty when it misses it.
Trace clipToConvex(const Ring& convex, const PlaneLine& line) {
  double lo = -kInf, hi = kInf;
  const std::size_t n = convex.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 a = convex[k], b = convex[(k + 1) % n];
    const Vec2 inward(-(b - a).y(), (b - a).x());  // left normal: inside for CCW
    const double num = inward.dot(line.o - a), den = inward.dot(line.d);
    if (std::abs(den) < 1e-15) {
      if (num < 0) return {};
      continue;
    }
    const double t = -num / den;
    if (den > 0) lo = std::max(lo, t); else hi = std::min(hi, t);
  }
  if (!(hi > lo)) return {};
  return {{lo, hi}};
}

/// The rhombus of line `own`, minus a thin double wedge around each other line of the plane whose
/// target it would contradict (an added rhombus over a piece of the other line that must stay
/// outside, a removed one over a piece that must stay inside), apex at the two lines' crossing:
/// an edit of one line then changes no other line's trace except at that one point. The wedge
/// is needed only where the two lines' consensus disagree about their crossing point (a triple
/// point of three planes); the section is then pinched there. Lines within 2 * 1° of parallel to
/// `own` get no wedge (they rarely cross an edit).
PolygonSet protectedEdit(const Ring& rhombus, const PlaneLine& own, const std::vector<GuardedLine>& others,
                         bool adding) {
  PolygonSet set(toPolygon(rhombus));
  Eigen::AlignedBox2d box;
  for (const Vec2& p : rhombus) box.extend(p);
  const double diameter = box.diagonal().norm();
  const Vec2 centre = box.center();
  for (const GuardedLine& g : others) {
    const PlaneLine& o = g.line;
    const Trace covered = clipToConvex(rhombus, o);
    if (covered.empty()) continue;
    const bool harmless = adding ? subtractTraces(covered, g.target).empty()
                                 : intersectTraces(covered, g.target).empty();
    if (harmless) continue;
    const double cross = own.d.x() * o.d.y() - own.d.y() * o.d.x();
    const double angle = std::asin(std::min(1.0, std::abs(cross)));
    if (angle < 1e-9) {
      // Parallel: a strip around the other line, half as wide as the lines are apart, keeps the
      // edit off it and leaves the own line alone.
      const double apart = distanceToLine(own.o, o);
      if (apart < 1e-9) continue;  // the same line
      const Vec2 across(-o.d.y(), o.d.x());
      const Vec2 foot = o.o + (centre - o.o).dot(o.d) * o.d;
      const double L = diameter + 1.0, h = 0.5 * apart;
      Polygon strip;
      for (const Vec2& v : {Vec2(foot - L * o.d - h * across), Vec2(foot + L * o.d - h * across),
                            Vec2(foot + L * o.d + h * across), Vec2(foot - L * o.d + h * across)})
        strip.push_back(Point(v.x(), v.y()));
      if (strip.orientation() != CGAL::COUNTERCLOCKWISE) strip.reverse_orientation();
      set.difference(strip);
      continue;
    }
    // X = own.o + s own.d = o.o + u o.d
    const Vec2 w = o.o - own.o;
    const double s = (w.x() * o.d.y() - w.y() * o.d.x()) / cross;
    const Vec2 X = own.o + s * own.d;
    const double half = std::min(1.0 * M_PI / 180.0, 0.25 * angle);
    const double D = (X - centre).norm() + diameter + 1.0;
    const double th = std::atan2(o.d.y(), o.d.x());
    const auto ray = [&](double a) -> Vec2 { return X + D * Vec2(std::cos(a), std::sin(a)); };
    for (const double side : {0.0, M_PI}) {
      const Polygon wedge = triangle(X, ray(th + side - half), ray(th + side + half));
      if (wedge.is_simple()) set.difference(wedge);
    }
  }
  return set;
}

/// A bump of the plane's deformation: points near `centre` slide along the line's direction d by
/// shift * psi(|p - centre| / radius), psi(r) = (1 - r^2)^2, so the crossing at `centre` moves
/// to `target` along the line. radius >= 2 |shift| keeps the map's Jacobian positive (|psi'| <=
/// 1.54), so the deformed plane is a diffeomorphic image: sections keep their topology.
struct Bump {
  Vec2 centre, target, d;
  double shift = 0, radius = 0;
};

double bumpWeight(double r) {
  if (r >= 1) return 0;
  const double q = 1 - r * r;
  return q * q;
}

/// Makes q a vertex of the sections' contours: 1 when a vertex is already there (within 1e-12
/// mm), 2 when q was inserted into the edge it lies on (within tol), 0 when it is on no edge.
int placeVertex(std::vector<Section>* sections, const Vec2& q, double tol) {
  Ring* bestRing = nullptr;
  std::size_t bestEdge = 0;
  double best = tol;
  for (Section& s : *sections) {
    std::vector<Ring*> rings{&s.outer};
    for (Ring& h : s.holes) rings.push_back(&h);
    for (Ring* ring : rings) {
      const std::size_t n = ring->size();
      for (std::size_t k = 0; k < n; ++k) {
        const Vec2& a = (*ring)[k];
        const Vec2& b = (*ring)[(k + 1) % n];
        if ((a - q).norm() <= kSame || (b - q).norm() <= kSame) return 1;
        const Vec2 ab = b - a;
        const double len2 = ab.squaredNorm();
        if (len2 == 0) continue;
        const double u = std::clamp((q - a).dot(ab) / len2, 0.0, 1.0);
        const double d = (a + u * ab - q).norm();
        if (d < best) best = d, bestRing = ring, bestEdge = k;
      }
    }
  }
  if (!bestRing) return 0;
  bestRing->insert(bestRing->begin() + std::ptrdiff_t(bestEdge + 1), q);
  return 2;
}


/// Whether t is an end of one of the intervals (where observation stops, not a contour).
bool onBoundaryOf(const Trace& c, double t) {
  for (const Interval& i : c)
    if (std::abs(i.t0 - t) <= kSame || std::abs(i.t1 - t) <= kSame) return true;
  return false;
}

/// `ring` moved by the bumps: its edges through a bump subdivided to a twelfth of its radius (only
/// the points that move are added: the rest of the edge stays as it was), then every point shifted
/// along its bump's line by the bump's weight; a bump's centre goes to its target exactly.
Ring deformRing(const Ring& ring, const std::vector<Bump>& chosen) {
  Ring dense;
  const std::size_t n = ring.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 a = ring[k], c = ring[(k + 1) % n];
    dense.push_back(a);
    double step = kInf;
    for (const Bump& b : chosen) {
      const Vec2 ac = c - a;
      const double u = ac.squaredNorm() > 0 ? std::clamp((b.centre - a).dot(ac) / ac.squaredNorm(), 0.0, 1.0) : 0.0;
      if ((a + u * ac - b.centre).norm() < b.radius) step = std::min(step, b.radius / 12);
    }
    if (std::isfinite(step)) {
      const int pieces = int(std::ceil((c - a).norm() / step));
      for (int i = 1; i < pieces; ++i) {
        const Vec2 q = a + (c - a) * (double(i) / pieces);
        bool inside = false;
        for (const Bump& b : chosen) inside = inside || (q - b.centre).norm() < b.radius;
        if (inside) dense.push_back(q);
      }
    }
  }
  for (Vec2& p : dense) {
    for (const Bump& b : chosen) {
      const double r = (p - b.centre).norm();
      if (r < 1e-12) {
        p = b.target;  // the consensus endpoint itself, the world point both planes share
        break;
      }
      p += b.shift * bumpWeight(r / b.radius) * b.d;
    }
  }
  return dense;
}

/// Matched endpoint moves become bumps: where the consensus and the current trace have
/// corresponding intervals, each endpoint moves to its counterpart by deforming the plane around
/// it. A bump must stay clear of every other line of the plane, every other crossing of the
/// contours with a line, and every other bump; where it cannot (or it would leave band_mm), the
/// endpoint is left to the Boolean edits. Returns the sections deformed (or the input, unchanged,
/// when no bump applies or a ring would stop being simple).
std::vector<Section> deformAlongLines(const CuttingPlane& cp, const std::vector<LineEdit>& edits,
                                      const std::vector<PlaneLine>& planeLines, double band,
                                      int* bumps, double* maxRadius) {
  struct Move {
    std::size_t edit;
    double from, to;
  };
  std::vector<Move> moves;
  for (std::size_t k = 0; k < edits.size(); ++k) {
    const LineEdit& e = edits[k];
    const Trace O = intersectTraces(e.current, e.common);
    if (O.size() != e.consensus.size()) continue;
    bool matched = true;
    for (std::size_t i = 0; i < O.size() && matched; ++i)
      matched = std::min(O[i].t1, e.consensus[i].t1) > std::max(O[i].t0, e.consensus[i].t0);
    if (!matched) continue;
    for (std::size_t i = 0; i < O.size(); ++i)
      for (const auto& [from, to] : {std::pair{O[i].t0, e.consensus[i].t0}, std::pair{O[i].t1, e.consensus[i].t1}})
        if (std::abs(to - from) > kSame && !onBoundaryOf(e.common, from)) moves.push_back({k, from, to});
  }
  if (moves.empty()) return cp.sections;
  // Every crossing of the contours with every line of the plane.
  std::vector<Vec2> crossings;
  for (const PlaneLine& l : planeLines)
    for (const Interval& i : sectionsTrace(cp.sections, l))
      for (const double t : {i.t0, i.t1}) crossings.push_back(l.at(t));
  std::vector<Bump> candidates;
  std::vector<std::size_t> lineOf;
  for (const Move& m : moves) {
    const LineEdit& e = edits[m.edit];
    Bump b;
    b.centre = cp.plane.toPlane(e.line.at(m.from));
    b.target = cp.plane.toPlane(e.line.at(m.to));
    b.d = lineInPlane(cp.plane, e.line).d;
    b.shift = m.to - m.from;
    b.radius = std::min(4 * std::abs(b.shift), band);
    candidates.push_back(b);
    lineOf.push_back(m.edit);
  }
  std::vector<Bump> chosen;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    Bump b = candidates[k];
    const PlaneLine own = lineInPlane(cp.plane, edits[lineOf[k]].line);
    for (const PlaneLine& l : planeLines)
      if ((l.o - own.o).norm() > 1e-9 || (l.d - own.d).norm() > 1e-12)
        b.radius = std::min(b.radius, 0.95 * distanceToLine(b.centre, l));
    for (const Vec2& q : crossings)
      if ((q - b.centre).norm() > 1e-9) b.radius = std::min(b.radius, 0.95 * (q - b.centre).norm());
    for (std::size_t j = 0; j < candidates.size(); ++j)
      if (j != k) b.radius = std::min(b.radius, 0.45 * (candidates[j].centre - b.centre).norm());
    if (b.radius >= 2 * std::abs(b.shift)) chosen.push_back(b);
  }
  if (chosen.empty()) return cp.sections;
  std::vector<Section> out = cp.sections;
  for (const Bump& b : chosen)
    if (placeVertex(&out, b.centre, 1e-6) == 0) return cp.sections;
  // Every other crossing near a bump becomes a vertex too, so that no subdivided piece of an
  // edge runs from a moved point to beyond a crossing and drags the crossing along.
  for (const Vec2& q : crossings)
    for (const Bump& b : chosen)
      if ((q - b.centre).norm() > 1e-9 && (q - b.centre).norm() < 4 * b.radius + 1.0) {
        placeVertex(&out, q, 1e-6);
        break;
      }
  for (Section& s : out) {
    s.outer = deformRing(s.outer, chosen);
    for (Ring& h : s.holes) h = deformRing(h, chosen);
    if (!toPolygon(s.outer).is_simple()) return cp.sections;
    for (const Ring& h : s.holes)
      if (!toPolygon(h).is_simple()) return cp.sections;
  }
  *bumps = int(chosen.size());
  for (const Bump& b : chosen) *maxRadius = std::max(*maxRadius, b.radius);
  return out;
}

/// The bounded polygons of a Boolean result as sections (rings of at least three vertices), each
/// with the label of the section of `touched` nearest inside: the one with the most negative
/// distance at the new outline's centroid (one label per plane in the usual single-material case).
std::vector<Section> sectionsOfPolygons(const std::vector<PolygonWithHoles>& result, const std::vector<Section>& touched) {
  std::vector<Section> edited;
  for (const PolygonWithHoles& p : result) {
    if (p.is_unbounded()) continue;
    Section s;
    s.outer = toRing(p.outer_boundary());
    if (s.outer.size() < 3) continue;
    for (auto h = p.holes_begin(); h != p.holes_end(); ++h) {
      Ring hr = toRing(*h);
      if (hr.size() >= 3) s.holes.push_back(std::move(hr));
    }
    if (!touched.empty()) {
      const Vec2 c = sectionCentroid(s);
      double best = kInf;
      for (const Section& t : touched) {
        const double d = signedDistanceToSections({t}, c);
        if (d < best) best = d, s.label = t.label;
      }
    }
    edited.push_back(std::move(s));
  }
  return edited;
}

/// All lines' edits of one plane in one Boolean operation.
/// @param lines  every line through the plane (measured pairs), edited or not: edits keep off them.
PlaneEditResult editPlane(const CuttingPlane& cp, std::vector<LineEdit> edits,
                          const std::vector<std::pair<CommonLine, Trace>>& lines, double band) {
  PlaneEditResult r;
  std::vector<PlaneLine> planeLines;
  for (const auto& l : lines) planeLines.push_back(lineInPlane(cp.plane, l.first));
  // Endpoint moves first, by deformation; what remains (intervals that appear or vanish, moves
  // too near another line) by exact Boolean edits.
  r.sections = deformAlongLines(cp, edits, planeLines, band, &r.bumps, &r.max_half_width);
  if (r.bumps > 0) {
    r.changed = true;
    for (LineEdit& e : edits) e.current = sectionsTrace(r.sections, lineInPlane(cp.plane, e.line));
  }
  std::vector<Ring> addRings, removeRings;
  std::vector<std::size_t> addLine, removeLine;  // which line of `lines` each rhombus is on
  for (const LineEdit& e : edits) {
    std::vector<Rhombus> add, remove;
    rhombiOfLine(e, band, &add, &remove);
    const PlaneLine l = lineInPlane(cp.plane, e.line);
    const Vec2 across(-l.d.y(), l.d.x());
    const auto ring = [&](const Rhombus& h) {
      // tips at the world points of the line (the same points the other plane gets)
      const Vec2 a = cp.plane.toPlane(e.line.at(h.s0)), b = cp.plane.toPlane(e.line.at(h.s1));
      const Vec2 m = 0.5 * (a + b);
      r.max_half_width = std::max(r.max_half_width, h.w);
      return Ring{a, m - h.w * across, b, m + h.w * across};
    };
    const std::size_t own = std::size_t(&e - edits.data());
    for (const Rhombus& h : add)
      if (h.w > 0) addRings.push_back(ring(h)), addLine.push_back(own);
    for (const Rhombus& h : remove)
      if (h.w > 0) removeRings.push_back(ring(h)), removeLine.push_back(own);
  }
  if (addRings.empty() && removeRings.empty()) return r;
  r.added = int(addRings.size());
  r.removed = int(removeRings.size());

  // Only the sections a rhombus reaches go through the Boolean operation.
  std::vector<Eigen::AlignedBox2d> boxes;
  for (const auto* rings : {&addRings, &removeRings})
    for (const Ring& q : *rings) {
      Eigen::AlignedBox2d b;
      for (const Vec2& p : q) b.extend(p);
      boxes.push_back(b);
    }
  std::vector<Section> kept, touched;
  for (const Section& s : r.sections) {
    const Eigen::AlignedBox2d sb = ringBounds(s.outer);
    bool hit = false;
    for (const auto& b : boxes) hit = hit || sb.intersects(b);
    (hit ? touched : kept).push_back(s);
  }
  std::vector<PolygonWithHoles> inputs;
  for (const Section& s : touched) {
    PolygonWithHoles p;
    if (!toPolygonWithHoles(s, &p)) {
      r.editable = false;
      r.added = r.removed = 0;
      r.max_half_width = 0;
      return r;
    }
    inputs.push_back(std::move(p));
  }
  // Per edited line, the plane's other lines with their targets (what its rhombi must keep off).
  std::vector<std::vector<GuardedLine>> guards(edits.size());
  for (std::size_t e = 0; e < edits.size(); ++e) {
    const PlaneLine own = lineInPlane(cp.plane, edits[e].line);
    for (std::size_t k = 0; k < planeLines.size(); ++k) {
      const PlaneLine& l = planeLines[k];
      if ((l.o - own.o).norm() > 1e-9 || std::abs(l.d.x() * own.d.y() - l.d.y() * own.d.x()) > 1e-12)
        guards[e].push_back({l, lines[k].second});
    }
  }
  PolygonSet set;
  set.join(inputs.begin(), inputs.end());
  for (std::size_t k = 0; k < addRings.size(); ++k)
    set.join(protectedEdit(addRings[k], lineInPlane(cp.plane, edits[addLine[k]].line), guards[addLine[k]], true));
  for (std::size_t k = 0; k < removeRings.size(); ++k)
    set.difference(protectedEdit(removeRings[k], lineInPlane(cp.plane, edits[removeLine[k]].line), guards[removeLine[k]], false));
  std::vector<PolygonWithHoles> result;
  set.polygons_with_holes(std::back_inserter(result));
  std::vector<Section> edited = sectionsOfPolygons(result, touched);
  std::sort(edited.begin(), edited.end(), [](const Section& x, const Section& y) {
    const Vec2 a = smallestVertex(x.outer), b = smallestVertex(y.outer);
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  r.sections = std::move(kept);
  r.sections.insert(r.sections.end(), edited.begin(), edited.end());
  r.changed = true;
  return r;
}

/// Shared vertices: every endpoint of an enforced pair's (now common) trace inside its common
/// region becomes a vertex of both polygons, at the same world point of the line. Marks each pair's
/// `agrees`; returns the vertices inserted per plane.
std::vector<int> shareTraceEndpoints(const std::vector<PlanePairTraces>& pairs, const ConformityParams& params,
                                     ConformityEnforcement& out) {
  const std::vector<PlanePairTraces> now = retrace(pairs, out.planes);
  std::vector<std::vector<Vec3>> points(out.planes.size());
  for (std::size_t k = 0; k < now.size(); ++k) {
    out.corrections[k].agrees = now[k].disagreement.symmetric_difference_mm <= params.tolerance_mm;
    if (!out.corrections[k].applied || !out.corrections[k].agrees) continue;
    const PlanePairTraces& p = now[k];
    for (const Interval& c : p.common)
      for (const Interval& i : p.trace_a)
        for (const double t : {i.t0, i.t1})
          if (t > c.t0 && t < c.t1) {
            points[std::size_t(p.a)].push_back(p.line.at(t));
            points[std::size_t(p.b)].push_back(p.line.at(t));
          }
  }
  std::vector<int> inserted(out.planes.size(), 0);
  tbb::parallel_for(std::size_t(0), out.planes.size(), [&](std::size_t i) {
    const double tol = 1e-6;
    for (const Vec3& x : points[i])
      inserted[i] += placeVertex(&out.planes[i].sections, out.planes[i].plane.toPlane(x), tol) == 2;
  });
  return inserted;
}

}  // namespace

Trace consensusTrace(const Trace& a, const Trace& b, const Trace& common, ConsensusMode mode) {
  switch (mode) {
    case ConsensusMode::intersection: return intersectTraces(intersectTraces(a, b), common);
    case ConsensusMode::union_: return intersectTraces(uniteTraces(a, b), common);
    case ConsensusMode::average: break;
  }
  return averageTrace(a, b, common);
}

ConformityEnforcement enforceConformity(const std::vector<CuttingPlane>& planes,
                                        const std::vector<PlanePairTraces>& pairs,
                                        const ConformityParams& params,
                                        const std::vector<PlanePairTraces>& unmeasured) {
  ConformityEnforcement out;
  out.planes = planes;
  out.corrections.resize(pairs.size());
  // Planes whose sections CGAL cannot take (a ring not simple) are never edited, nor their
  // partners along their lines: a pair is edited on both sides or not at all.
  std::vector<char> notEditable(planes.size(), 0);
  tbb::parallel_for(std::size_t(0), planes.size(), [&](std::size_t i) {
    PolygonWithHoles p;
    for (const Section& s : planes[i].sections)
      if (!toPolygonWithHoles(s, &p)) notEditable[i] = 1;
  });
  for (int round = 0; round < params.max_rounds; ++round) {
    const std::vector<PlanePairTraces> now = retrace(pairs, out.planes);
    std::vector<std::vector<LineEdit>> edits(planes.size());
    std::vector<std::optional<Trace>> consensusOf(now.size());  // this round's, when enforced
    bool any = false;
    for (std::size_t k = 0; k < now.size(); ++k) {
      const PlanePairTraces& p = now[k];
      PairCorrection& c = out.corrections[k];
      if (c.over_max || c.not_editable || p.disagreement.symmetric_difference_mm <= params.tolerance_mm) continue;
      if (notEditable[std::size_t(p.a)] || notEditable[std::size_t(p.b)]) {
        c.not_editable = true;
        continue;
      }
      const Trace T = consensusTrace(p.trace_a, p.trace_b, p.common, params.mode);
      // The largest change of either trace; in later rounds, a pair disturbed by its planes'
      // other edits is held to the same limit.
      const double ca = longestInterval(intersectTraces(symmetricDifference(p.trace_a, T), p.common));
      const double cb = longestInterval(intersectTraces(symmetricDifference(p.trace_b, T), p.common));
      c.correction_a_mm = std::max(c.correction_a_mm, ca);
      c.correction_b_mm = std::max(c.correction_b_mm, cb);
      if (std::max(ca, cb) > params.max_correction_mm) {
        c.over_max = !c.applied;  // a pair already enforced stays enforced, and is reported below
        continue;
      }
      c.applied = true;
      c.consensus = T;
      consensusOf[k] = T;
      edits[std::size_t(p.a)].push_back({p.line, p.trace_a, T, p.common});
      edits[std::size_t(p.b)].push_back({p.line, p.trace_b, T, p.common});
      any = true;
    }
    if (!any) break;
    // Every line through each plane with the trace it must end this round with.
    std::vector<std::vector<std::pair<CommonLine, Trace>>> linesOf(planes.size());
    for (const PlanePairTraces& p : unmeasured) {
      linesOf[std::size_t(p.a)].push_back({p.line, p.trace_a});
      linesOf[std::size_t(p.b)].push_back({p.line, p.trace_b});
    }
    for (std::size_t k = 0; k < now.size(); ++k) {
      const PlanePairTraces& p = now[k];
      const bool edited = consensusOf[k].has_value();
      for (const auto& [plane, trace] : {std::pair{p.a, &p.trace_a}, std::pair{p.b, &p.trace_b}})
        linesOf[std::size_t(plane)].push_back(
            {p.line, edited ? uniteTraces(*consensusOf[k], subtractTraces(*trace, p.common)) : *trace});
    }
    std::vector<PlaneEditResult> results(planes.size());
    tbb::parallel_for(std::size_t(0), planes.size(), [&](std::size_t i) {
      if (!edits[i].empty()) results[i] = editPlane(out.planes[i], edits[i], linesOf[i], params.band_mm);
    });
    bool changed = false;
    for (std::size_t i = 0; i < planes.size(); ++i) {
      if (edits[i].empty()) continue;
      if (!results[i].editable) {  // cannot happen: checked before the first round
        notEditable[i] = 1;
        continue;
      }
      out.planes[i].sections = std::move(results[i].sections);
      out.rhombi_added += results[i].added;
      out.bumps += results[i].bumps;
      out.rhombi_removed += results[i].removed;
      out.max_half_width_mm = std::max(out.max_half_width_mm, results[i].max_half_width);
      changed = changed || results[i].changed;
    }
    if (!changed) break;
    ++out.rounds;
  }
  for (std::size_t i = 0; i < planes.size(); ++i)
    if (notEditable[i]) out.planes_not_editable.push_back(int(i));

  const std::vector<int> inserted = shareTraceEndpoints(pairs, params, out);
  for (std::size_t i = 0; i < planes.size(); ++i) {
    out.vertices_shared += inserted[i];
    const auto& a = out.planes[i].sections;
    const auto& b = planes[i].sections;
    bool same = a.size() == b.size();
    for (std::size_t s = 0; same && s < a.size(); ++s) same = a[s].outer == b[s].outer && a[s].holes == b[s].holes;
    out.planes_edited += !same;
  }
  return out;
}

}  // namespace xsect
