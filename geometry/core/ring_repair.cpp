// Crossing contours made simple (see ring_repair.h). CGAL headers stay here.
#include "geometry/core/ring_repair.h"

#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arrangement_with_history_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Surface_sweep_2_algorithms.h>

#include <deque>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "geometry/core/polygon.h"
#include "geometry/core/ring_validity.h"

namespace xsect {

namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Traits = CGAL::Arr_segment_traits_2<K>;
using Arrangement = CGAL::Arrangement_with_history_2<Traits>;
using Point = K::Point_2;
using Segment = Traits::Curve_2;
using Loop = std::vector<Point>;

Point exact(const Vec2& p) { return Point(p.x(), p.y()); }

/// The directed segments of a closed loop.
void addSegments(const Loop& loop, std::vector<Segment>& out) {
  for (std::size_t i = 0, n = loop.size(); i < n; ++i)
    if (loop[i] != loop[(i + 1) % n]) out.emplace_back(loop[i], loop[(i + 1) % n]);
}

/// The loop cut where it passes a point twice (a region touching itself at a vertex, a hole
/// touching its outer boundary) into loops that pass each point once, appended to `out` (those of
/// at least three points).
void splitAtRepeatedPoints(Loop loop, std::vector<Loop>& out) {
  Loop stack;
  std::map<Point, std::size_t> at;  // point -> its index in `stack`
  for (const Point& p : loop) {
    const auto it = at.find(p);
    if (it == at.end()) {
      at.emplace(p, stack.size());
      stack.push_back(p);
      continue;
    }
    // A sub-loop from p's first visit to here: closed, taken out.
    Loop sub(stack.begin() + std::ptrdiff_t(it->second), stack.end());
    for (std::size_t i = it->second + 1; i < stack.size(); ++i) at.erase(stack[i]);
    stack.resize(it->second + 1);
    if (sub.size() >= 3) out.push_back(std::move(sub));
  }
  if (stack.size() >= 3) out.push_back(std::move(stack));
}

/// The boundary loops of the region of the arrangement of `segments` (directed: a segment counts
/// +1 for the face on its left) whose winding number `inside` accepts, each with the region on
/// its left (counter-clockwise outer loops, clockwise holes).
template <typename Inside>
std::vector<Loop> regionLoops(const std::vector<Segment>& segments, const Inside& inside) {
  Arrangement arr;
  CGAL::insert(arr, segments.begin(), segments.end());
  // Winding numbers by a walk across edges from the unbounded face (0): crossing a halfedge from
  // its left face to its right one subtracts the segments running along it in its direction and
  // adds those running against it.
  std::map<const void*, long> winding;  // by the face's address
  std::deque<Arrangement::Face_const_handle> queue{arr.unbounded_face()};
  winding[&*arr.unbounded_face()] = 0;
  const auto along = [&](Arrangement::Halfedge_const_handle h) {
    long s = 0;
    const bool leftToRight = h->direction() == CGAL::ARR_LEFT_TO_RIGHT;
    for (auto c = arr.originating_curves_begin(h); c != arr.originating_curves_end(h); ++c) {
      const bool curveLeftToRight = CGAL::compare_xy(c->source(), c->target()) == CGAL::SMALLER;
      s += curveLeftToRight == leftToRight ? 1 : -1;
    }
    return s;
  };
  const auto visit = [&](Arrangement::Halfedge_const_handle first, long w) {
    auto h = first;
    do {
      const auto other = h->twin()->face();
      if (!winding.count(&*other)) {
        winding[&*other] = w - along(h);
        queue.push_back(other);
      }
      h = h->next();
    } while (h != first);
  };
  while (!queue.empty()) {
    const auto f = queue.front();
    queue.pop_front();
    const long w = winding[&*f];
    if (!f->is_unbounded()) visit(f->outer_ccb(), w);
    for (auto hole = f->inner_ccbs_begin(); hole != f->inner_ccbs_end(); ++hole) visit(*hole, w);
  }
  const auto in = [&](Arrangement::Face_const_handle f) { return inside(winding.at(&*f)); };
  // The boundary: halfedges with the region on the left and not on the right, chained around
  // each vertex through the region's faces so that loops touching at a vertex stay apart.
  std::vector<Loop> loops;
  std::set<const void*> done;  // by the halfedge's address
  for (auto e = arr.halfedges_begin(); e != arr.halfedges_end(); ++e) {
    const Arrangement::Halfedge_const_handle start = e;
    if (!in(start->face()) || in(start->twin()->face()) || done.count(&*start)) continue;
    Loop loop;
    auto h = start;
    do {
      done.insert(&*h);
      loop.push_back(h->source()->point());
      auto next = h->next();
      while (in(next->twin()->face())) next = next->twin()->next();
      h = next;
    } while (h != start && !done.count(&*h));
    splitAtRepeatedPoints(std::move(loop), loops);
  }
  return loops;
}

K::FT loopArea(const Loop& loop) {
  K::FT a = 0;
  for (std::size_t i = 0, n = loop.size(); i < n; ++i)
    a += loop[i].x() * loop[(i + 1) % n].y() - loop[(i + 1) % n].x() * loop[i].y();
  return a / 2;
}

Ring rounded(const Loop& loop) {
  Ring r;
  r.reserve(loop.size());
  for (const Point& p : loop) r.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()));
  return withoutRepeatedVertices(r);
}

/// Whether two simple rings sharing vertex r[i] = q[j] only touch there: q's two edges at the
/// vertex lie in the same one of the two angular sectors r's edges make (exact directions).
bool touchOnly(const Ring& r, std::size_t i, const Ring& q, std::size_t j) {
  const Point v = exact(r[i]);
  const auto dir = [&](const Vec2& p) { return K::Direction_2(exact(p) - v); };
  const K::Direction_2 a0 = dir(r[(i + r.size() - 1) % r.size()]), a1 = dir(r[(i + 1) % r.size()]);
  const K::Direction_2 b0 = dir(q[(j + q.size() - 1) % q.size()]), b1 = dir(q[(j + 1) % q.size()]);
  if (b0 == a0 || b0 == a1 || b1 == a0 || b1 == a1) return false;  // a shared edge direction: overlap
  return b0.counterclockwise_in_between(a0, a1) == b1.counterclockwise_in_between(a0, a1);
}

}  // namespace

bool ringsAreSimpleAndDisjoint(const std::vector<Ring>& rings) {
  std::vector<Segment> segments;
  std::map<std::pair<double, double>, std::pair<std::size_t, std::size_t>> vertices;  // -> (ring, index)
  for (std::size_t k = 0; k < rings.size(); ++k) {
    const Ring& r = rings[k];
    if (!ringIsSimple(r)) return false;
    for (std::size_t i = 0; i < r.size(); ++i) {
      const auto [it, fresh] = vertices.emplace(std::make_pair(r[i].x(), r[i].y()), std::make_pair(k, i));
      // A vertex of two rings: touching there is allowed (contours of a .contour file may),
      // crossing or running along each other is not.
      if (!fresh && !touchOnly(rings[it->second.first], it->second.second, r, i)) return false;
    }
    Loop loop;
    for (const Vec2& p : r) loop.push_back(exact(p));
    addSegments(loop, segments);
  }
  // Crossings in the segments' interiors (a vertex on another ring's edge among them); shared
  // endpoints are not interior points.
  return !CGAL::do_curves_intersect(segments.begin(), segments.end());
}

std::string repairWarning(const std::string& where, const RingRepair& r) {
  std::ostringstream s;
  s.precision(6);
  s << where << ": crossing contours made simple (" << r.outers_in << " outer rings and " << r.holes_in
    << " holes -> " << r.outers.size() << " and " << r.holes.size() << "; area " << r.area_before << " -> "
    << r.area_after << " mm², by the positive winding of their oriented lobes; input.repair_contours: false "
    << "refuses them)";
  return s.str();
}

RingRepair repairRings(const std::vector<Ring>& outers, const std::vector<Ring>& holes) {
  RingRepair out;
  out.outers_in = outers.size();
  out.holes_in = holes.size();
  std::vector<Ring> all;
  for (const Ring& r : outers) {
    out.area_before += std::abs(signedArea(r));
    all.push_back(withoutRepeatedVertices(r));
  }
  for (const Ring& r : holes) {
    out.area_before -= std::abs(signedArea(r));
    all.push_back(withoutRepeatedVertices(r));
  }
  if (ringsAreSimpleAndDisjoint(all)) {
    out.outers = outers;
    out.holes = holes;
    out.area_after = out.area_before;
    return out;
  }
  out.changed = true;
  // 1. Each ring's own region by the even-odd rule; its loops signed by the ring's role.
  std::vector<Segment> signedLoops;
  for (std::size_t k = 0; k < all.size(); ++k) {
    const Ring& r = all[k];
    if (r.size() < 3) continue;
    const bool hole = k >= outers.size();
    Loop ring;
    for (const Vec2& p : r) ring.push_back(exact(p));
    std::vector<Loop> lobes;
    if (ringIsSimple(r)) {
      lobes.push_back(ring);
      if (loopArea(ring) < 0) std::reverse(lobes.back().begin(), lobes.back().end());
    } else {
      std::vector<Segment> own;
      addSegments(ring, own);
      lobes = regionLoops(own, [](long w) { return w % 2 != 0; });
    }
    for (Loop& lobe : lobes) {
      if (hole) std::reverse(lobe.begin(), lobe.end());
      addSegments(lobe, signedLoops);
    }
  }
  // 2. The region of positive winding.
  for (Loop& loop : regionLoops(signedLoops, [](long w) { return w > 0; })) {
    const K::FT a = loopArea(loop);
    Ring r = rounded(loop);
    if (r.size() < 3) continue;
    const double area = CGAL::to_double(a);
    out.area_after += area;
    (a > 0 ? out.outers : out.holes).push_back(std::move(r));
  }
  // Rounded to doubles, crossing points closer than a double can tell apart could meet again.
  std::vector<Ring> result = out.outers;
  result.insert(result.end(), out.holes.begin(), out.holes.end());
  if (!ringsAreSimpleAndDisjoint(result))
    throw std::invalid_argument("the repaired contours cross again once their crossing points are rounded to double "
                                "precision (features under 1e-15 of the coordinates)");
  return out;
}

}  // namespace xsect
