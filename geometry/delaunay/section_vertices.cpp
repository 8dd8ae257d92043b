// Section-vertices of method 3 from the arrangement's contour points (see section_vertices.h).
#include "geometry/delaunay/section_vertices.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_set>
#include <functional>
#include <tuple>

#include "geometry/core/near_points.h"
#include "geometry/core/polygon.h"
#include "geometry/core/section_locator.h"
#include "geometry/delaunay/delaunay_reconstruction.h"

namespace xsect {

namespace {

/// Adds `cell` to v's cells with the sides s0, s1, s2 of v's planes (0: unknown, e.g. a contour
/// vertex merged with a trace point at the same coordinates knows no side of the trace's plane).
/// A cell already there keeps its sides and takes the ones it does not know: a cell lies on one
/// side of each plane, so two sources never disagree on a known side.
void addCell(SectionVertex& v, int cell, int s0, int s1, int s2 = 0) {
  if (cell < 0) return;
  const std::array<int, 3> s{s0, s1, s2};
  for (PointCell& c : v.cells)
    if (c.cell == cell) {
      for (std::size_t k = 0; k < 3; ++k)
        if (c.side[k] == 0) c.side[k] = std::int8_t(s[k]);
      return;
    }
  v.cells.push_back({cell, {std::int8_t(s0), std::int8_t(s1), std::int8_t(s2)}});
}

void sortCells(SectionVertex& v) {
  std::sort(v.cells.begin(), v.cells.end(), [](const PointCell& a, const PointCell& b) { return a.cell < b.cell; });
}

/// x moved onto the planes `on` (-1: none) in turn, twice: a trace point computed in one plane's
/// coordinates (a crossing interpolated along a contour edge, or the midpoint of a merged pair)
/// lies on the other plane only up to the interpolation's rounding, and a point of a plane lifted
/// off it by rounding lets a cell's Delaunay triangles of that plane cross its contour edges.
Vec3 ontoPlanes(Vec3 x, const std::vector<CuttingPlane>& planes, const std::array<int, 3>& on) {
  for (int round = 0; round < 2; ++round)
    for (int k = 2; k >= 0; --k)
      if (on[std::size_t(k)] >= 0) {
        const Plane& P = planes[std::size_t(on[std::size_t(k)])].plane;
        x -= P.signedDistance(x) * P.normal;
      }
  return x;
}

/// Where P's contour crosses Q and Q's contour crosses P, both samples stand for one point of the
/// object's surface on the line P ∩ Q (the sections conform there, up to their sampling): pairs
/// nearer than `tolerance` (mutual nearest) and bounding the same cells become one point on both
/// rings, at their midpoint.
/// Two nearly coincident points would otherwise leave slivers that no triangulation of the two
/// planes agrees on.
void mergeTracePairs(SectionVertices& sv, double tolerance) {
  std::map<std::pair<int, int>, std::array<std::vector<int>, 2>> byLine;
  for (std::size_t id = 0; id < sv.points.size(); ++id) {
    const SectionVertex& v = sv.points[id];
    if (v.kind != SectionVertex::trace || v.planes[1] < 0) continue;
    const int p = v.planes[0], q = v.planes[1];
    byLine[{std::min(p, q), std::max(p, q)}][p < q ? 0 : 1].push_back(int(id));
  }
  std::vector<int> alias(sv.points.size());
  for (std::size_t k = 0; k < alias.size(); ++k) alias[k] = int(k);
  for (auto& [line, sides] : byLine) {
    const auto nearest = [&](int a, const std::vector<int>& others) {
      int best = -1;
      double bd = tolerance;
      for (const int b : others) {
        const double d = (sv.points[std::size_t(a)].x - sv.points[std::size_t(b)].x).norm();
        if (d < bd) {
          bd = d;
          best = b;
        }
      }
      return best;
    };
    for (const int a : sides[0]) {
      const int b = nearest(a, sides[1]);
      if (b < 0 || nearest(b, sides[0]) != a) continue;
      SectionVertex& A = sv.points[std::size_t(a)];
      SectionVertex& B = sv.points[std::size_t(b)];
      // Only points in the same cells (no third plane passes between them): otherwise the merged
      // point would bound cells on both sides of that plane.
      bool same = A.cells.size() == B.cells.size();
      for (std::size_t k = 0; k < A.cells.size() && same; ++k) same = A.cells[k].cell == B.cells[k].cell;
      if (!same) continue;
      A.x = 0.5 * (A.x + B.x);
      // B's planes are (Q, P): its sides swap slots.
      for (const PointCell& c : B.cells) addCell(A, c.cell, c.side[1], c.side[0], 0);
      sortCells(A);
      B.cells.clear();
      alias[std::size_t(b)] = a;
    }
  }
  for (SampledRing& r : sv.rings)
    for (int& id : r.points) id = alias[std::size_t(id)];
}

/// Section-vertices added one by one, each merged with an earlier one that coincides up to
/// rounding: a contour vertex on another plane's trace (which enforced conformity makes a vertex of
/// both planes' polygons), a trace point at a corner of three planes. Measured on the jittered torus
/// with enforced conformity: 37624 pairs of section-vertices 1e-15 to 7e-13 mm apart (sample
/// spacing 1 mm), whose slivers left 268 contour edges that no conformity round made Delaunay and
/// the glued boundary open (89 edges). The merge distance is a ten-millionth of the sample
/// spacing: far below every distance the method makes (the branching points' jitter is a tenth
/// of it; eight conformity rounds halve an edge to 1/256 of it). Of the points within it
/// (near_points.h), the nearest (then the first) takes the new one.
class VertexMerger {
 public:
  VertexMerger(SectionVertices& sv, double merge, std::size_t expected) : sv_(sv), merge_(merge), near_(merge, expected) {}
  double distance() const { return merge_; }

  /// The id of the point at x: an earlier one within the merge distance (taking v's planes and
  /// cells), else v itself, added.
  int add(const Vec3& x, SectionVertex v) {
    int found = -1;
    double best = merge_;
    near_.forEachCandidate(x, [&](int id) {
      const double d = (sv_.points[std::size_t(id)].x - x).norm();
      if (d < best || (d == best && found >= 0 && id < found)) {
        best = d;
        found = id;
      }
    });
    if (found >= 0) {
      // One point: it lies on the planes of both, in the cells of both, with the sides of each
      // cell re-read in the merged order, at the position of the one on more planes (a corner's
      // is solved on all three; a trace point is projected onto both planes below).
      SectionVertex& old = sv_.points[std::size_t(found)];
      std::array<int, 3> planesOf = old.planes;
      if (planeCount(v.planes) > planeCount(old.planes)) old.x = x;
      for (const int p : v.planes)
        if (p >= 0 && !old.on(p))
          for (int& slot : planesOf)
            if (slot < 0) {
              slot = p;
              break;
            }
      const auto remap = [&](const PointCell& c, const std::array<int, 3>& from) {
        std::array<int, 3> side{0, 0, 0};
        for (int k = 0; k < 3; ++k)
          for (int j = 0; j < 3; ++j)
            if (planesOf[std::size_t(k)] >= 0 && from[std::size_t(j)] == planesOf[std::size_t(k)]) side[std::size_t(k)] = c.side[std::size_t(j)];
        return side;
      };
      std::vector<PointCell> cells = std::move(old.cells);
      const std::array<int, 3> oldPlanes = old.planes;
      old.cells.clear();
      old.planes = planesOf;
      // A contour point now on two planes is a trace point (projected onto both below).
      if (old.kind == SectionVertex::contour && planeCount(planesOf) >= 2) old.kind = SectionVertex::trace;
      for (const PointCell& c : v.cells) {
        const auto side = remap(c, v.planes);
        addCell(old, c.cell, side[0], side[1], side[2]);
      }
      for (const PointCell& c : cells) {
        const auto side = remap(c, oldPlanes);
        addCell(old, c.cell, side[0], side[1], side[2]);
      }
      sortCells(old);
      return found;
    }
    v.x = x;
    sortCells(v);
    sv_.points.push_back(std::move(v));
    near_.add(int(sv_.points.size()) - 1, x);
    return int(sv_.points.size()) - 1;
  }

 private:
  static int planeCount(const std::array<int, 3>& q) { return int(q[0] >= 0) + int(q[1] >= 0) + int(q[2] >= 0); }

  SectionVertices& sv_;
  double merge_;
  NearPoints near_;
};

/// The rings: the arrangement's contour points grouped by (plane, section, ring), sorted along the
/// ring, each a section-vertex; rings sampled too coarsely as below.
void addRings(const std::vector<CuttingPlane>& planes, const SectionArrangement& arr, VertexMerger& merger,
              SectionVertices& sv) {
  std::map<std::tuple<int, int, int>, std::vector<std::pair<double, std::size_t>>> byRing;
  for (std::size_t q = 0; q < arr.points.size(); ++q) {
    const SectionPoint& sp = arr.points[q];
    if (sp.kind == SectionPoint::sample || sp.ring < 0) continue;
    byRing[{sp.plane, sp.section, sp.ring}].push_back({sp.along, q});
  }
  for (auto& [key, list] : byRing) {
    const auto [p, s, r] = key;
    std::stable_sort(list.begin(), list.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    const CuttingPlane& cp = planes[std::size_t(p)];
    SampledRing ring{p, s, r, {}};
    // Too few samples (fewer than three apart: a ring shorter than about three spacings): evenly
    // spaced original vertices in the cells of the first sample, when the ring lies in them (no
    // trace point: it crosses no plane). One that crosses a plane is below the sampling and is
    // left out (counted), before any of its points is made: its original vertices would lie in
    // several cells, and its contour edges would cross a plane (enforced conformity makes such
    // rings: a rhombus whose diagonal is a 0.08 mm piece of a trace, measured on the jittered
    // torus, seed 5, with 0.5 mm samples).
    std::vector<Vec3> apart;
    for (const auto& [along, q] : list) {
      const Vec3 x = cp.plane.toWorld(arr.points[q].p);
      if (std::all_of(apart.begin(), apart.end(), [&](const Vec3& y) { return (x - y).norm() >= merger.distance(); })) apart.push_back(x);
      if (apart.size() == 3) break;
    }
    if (apart.size() < 3) {
      const bool crosses = std::any_of(list.begin(), list.end(), [&](const auto& a) {
        return arr.points[a.second].kind == SectionPoint::trace;
      });
      if (crosses) {
        ++sv.rings_dropped;
        continue;
      }
      const Section& sec = cp.sections[std::size_t(s)];
      const Ring& orig = r == 0 ? sec.outer : sec.holes[std::size_t(r - 1)];
      if (orig.size() >= 3 && !list.empty()) {
        const SectionPoint& first = arr.points[list.front().second];
        const std::size_t n = std::min<std::size_t>(orig.size(), 8);
        for (std::size_t k = 0; k < n; ++k) {
          SectionVertex v;
          v.planes = {p, -1, -1};
          v.section = s;
          v.kind = SectionVertex::contour;
          for (int side = 0; side < 2; ++side) addCell(v, first.cell[std::size_t(side)], side == 0 ? -1 : 1, 0);
          const int id = merger.add(cp.plane.toWorld(orig[k * orig.size() / n]), v);
          if (ring.points.empty() || ring.points.back() != id) ring.points.push_back(id);
        }
      }
    } else {
      for (const auto& [along, q] : list) {
        const SectionPoint& sp = arr.points[q];
        SectionVertex v;
        v.planes = {p, sp.trace_plane, -1};
        v.section = s;
        v.kind = sp.kind == SectionPoint::trace ? SectionVertex::trace : SectionVertex::contour;
        // Sides: cell[0] lies on the negative side of the own plane, cell[1] on the positive; for
        // a trace point `cell` on the positive side of the trace plane, `cell_alt` on its negative.
        for (int side = 0; side < 2; ++side) {
          if (sp.trace_plane >= 0) {
            addCell(v, sp.cell[std::size_t(side)], side == 0 ? -1 : 1, 1);
            addCell(v, sp.cell_alt[std::size_t(side)], side == 0 ? -1 : 1, -1);
          } else {
            addCell(v, sp.cell[std::size_t(side)], side == 0 ? -1 : 1, 0);
          }
        }
        const int id = merger.add(cp.plane.toWorld(sp.p), v);
        if (ring.points.empty() || (ring.points.back() != id && ring.points.front() != id)) ring.points.push_back(id);
      }
    }
    if (ring.points.size() >= 3) sv.rings.push_back(std::move(ring));
  }
}

/// A corner: three planes meeting inside a section of one of them (`holder` of holders, the other
/// two planes a and b), at x.
struct CornerAt {
  int a, b;  ///< the two other planes
  Vec3 x;
};

/// The corners inside each section (plane, section) of `holders`, per holder.
std::vector<std::vector<CornerAt>> cornersInSections(const std::vector<CuttingPlane>& planes,
                                                     const std::vector<std::pair<int, int>>& holders) {
  // Per section in parallel: a pure search, about k² plane pairs per section for k planes.
  std::vector<std::vector<CornerAt>> found(holders.size());
  tbb::parallel_for(std::size_t(0), holders.size(), [&](std::size_t h) {
    const std::size_t i = std::size_t(holders[h].first);
    const CuttingPlane& cp = planes[i];
    const Section& sec = cp.sections[std::size_t(holders[h].second)];
    const Eigen::AlignedBox2d box = ringBounds(sec.outer);
    const Vec3 centre = cp.plane.toWorld(box.center());
    const double radius = 0.5 * box.diagonal().norm() * (1 + 1e-9) + 1e-9;
    std::vector<int> crossing;
    for (std::size_t j = 0; j < planes.size(); ++j)
      if (j != i && std::abs(planes[j].plane.signedDistance(centre)) <= radius) crossing.push_back(int(j));
    // Each crossing plane's trace on plane i, n·q = c in plane coordinates (n of unit length, or
    // zero for a plane nearly parallel to i): two traces meeting outside the section's box by
    // more than a millionth of the coordinates' size meet at no corner inside it. That margin is
    // far beyond the rounding of both solves where it is used: only for well-conditioned triples,
    // |det| = len_a len_b |det2| > 1e-2 (the 3D solve below skips those under 1e-6). Most pairs
    // meet outside (random-800: 4% of the pairs are corners); the others are solved in 3D as before.
    const Plane& P = cp.plane;
    std::vector<Vec2> tn(crossing.size());
    std::vector<double> tc(crossing.size()), tlen(crossing.size());
    double scale = box.diagonal().norm() + box.center().norm() + P.origin.norm();
    for (std::size_t a = 0; a < crossing.size(); ++a) {
      const Plane& Q = planes[std::size_t(crossing[a])].plane;
      const Vec2 n(Q.normal.dot(P.u), Q.normal.dot(P.v));
      tlen[a] = n.norm();
      tn[a] = tlen[a] > 1e-6 ? Vec2(n / tlen[a]) : Vec2::Zero();
      tc[a] = tlen[a] > 1e-6 ? Q.normal.dot(Q.origin - P.origin) / tlen[a] : 0;
      scale = std::max(scale, box.diagonal().norm() + box.center().norm() + P.origin.norm() + (Q.origin - P.origin).norm());
    }
    const double slack = 1e-6 * scale + 1e-9;
    Eigen::AlignedBox2d wide = box;
    wide.min().array() -= slack;
    wide.max().array() += slack;
    for (std::size_t a = 0; a < crossing.size(); ++a)
      for (std::size_t b = a + 1; b < crossing.size(); ++b) {
        const double det2 = tn[a].x() * tn[b].y() - tn[a].y() * tn[b].x();
        if (tlen[a] * tlen[b] * std::abs(det2) > 1e-2) {
          const Vec2 meet((tc[a] * tn[b].y() - tc[b] * tn[a].y()) / det2, (tn[a].x() * tc[b] - tn[b].x() * tc[a]) / det2);
          if (!wide.contains(meet)) continue;
        }
        const Plane& Q = planes[std::size_t(crossing[a])].plane;
        const Plane& R = planes[std::size_t(crossing[b])].plane;
        Eigen::Matrix3d M;
        M.row(0) = cp.plane.normal.transpose();
        M.row(1) = Q.normal.transpose();
        M.row(2) = R.normal.transpose();
        // Nearly parallel planes meet far away or along a line: no corner.
        if (std::abs(M.determinant()) < 1e-6) continue;
        const Vec3 x = M.partialPivLu().solve(
            Vec3(cp.plane.normal.dot(cp.plane.origin), Q.normal.dot(Q.origin), R.normal.dot(R.origin)));
        // Beyond the outer ring's bounds (widened: the ring walk's crossings round by an ulp or
        // so) is outside the section: the same answer, without the walk.
        const Vec2 q = cp.plane.toPlane(x);
        if (!wide.contains(q) || !sectionContains(sec, q)) continue;
        found[h].push_back({crossing[a], crossing[b], x});
      }
  });
  return found;
}

/// The corners (three planes meeting inside a section of one of them), found per section in
/// parallel, then added in order.
void addCorners(const std::vector<CuttingPlane>& planes, const SectionArrangement& arr, VertexMerger& merger,
                SectionVertices& sv) {
  std::vector<std::pair<int, int>> holders;  // (plane, section)
  for (std::size_t i = 0; i < planes.size(); ++i)
    for (std::size_t s = 0; s < planes[i].sections.size(); ++s) holders.push_back({int(i), int(s)});
  const std::vector<std::vector<CornerAt>> found = cornersInSections(planes, holders);
  // Each corner once, where it was found first (inside sections of all three planes it is found
  // three times: random-800's 1 578 718 finds are 526 390 corners); the cells around each in
  // parallel (exact signs against every plane); then numbered and merged in order.
  struct CornerFirst {
    int holder;
    const CornerAt* at;
  };
  std::vector<CornerFirst> firsts;
  {
    struct TripleHash {
      std::size_t operator()(const std::array<int, 3>& k) const {
        std::uint64_t h = 0;
        for (const int p : k) h = (h ^ std::uint64_t(std::uint32_t(p))) * 0x100000001b3ull + 0x9e3779b97f4a7c15ull;
        return std::size_t(h ^ (h >> 29));
      }
    };
    std::unordered_set<std::array<int, 3>, TripleHash> seen;
    for (std::size_t h = 0; h < holders.size(); ++h)
      for (const CornerAt& c : found[h]) {
        std::array<int, 3> key{holders[h].first, c.a, c.b};
        std::sort(key.begin(), key.end());
        if (seen.insert(key).second) firsts.push_back({int(h), &c});
      }
  }
  std::vector<CellsAround> around(firsts.size());
  tbb::parallel_for(std::size_t(0), firsts.size(), [&](std::size_t f) {
    const CornerAt& c = *firsts[f].at;
    around[f] = cellsAround(arr, planes, c.x, {holders[std::size_t(firsts[f].holder)].first, c.a, c.b});
  });
  // Cells no section point met (a small cell inside the object, bounded by sections only and
  // reached by no contour): numbered after the arrangement's, by their keys.
  std::map<std::array<std::uint64_t, 2>, int> unseen;
  for (std::size_t f = 0; f < firsts.size(); ++f) {
    const auto [i, s] = holders[std::size_t(firsts[f].holder)];
    const CornerAt& c = *firsts[f].at;
    std::vector<int>& cells = around[f].cells;
    for (std::size_t m = 0; m < cells.size(); ++m)
      if (cells[m] < 0) cells[m] = unseen.emplace(around[f].keys[m], sv.cells + int(unseen.size())).first->second;
    SectionVertex v;
    v.planes = {i, c.a, c.b};
    v.section = s;
    v.kind = SectionVertex::corner;
    for (std::size_t m = 0; m < cells.size(); ++m)
      addCell(v, cells[m], (m & 1) ? 1 : -1, (m & 2) ? 1 : -1, (m & 4) ? 1 : -1);
    merger.add(c.x, v);  // never without cells: every one around is numbered
    around[f] = CellsAround{};
  }
  sv.cells += int(unseen.size());
}

/// The branching points (thesis ch. 3), each moved off the lattice's ties, or dropped on a trace
/// (below); their sides of their plane unknown yet (readBranchingSides).
void addBranchingPoints(const std::vector<CuttingPlane>& planes, const SectionArrangement& arr,
                        const std::vector<BranchingPoint>& branching, VertexMerger& merger) {
  // Branching points come on a square lattice: four of them are often cocircular, and the
  // Delaunay structure of such ties on a plane whose points are coplanar only up to rounding
  // differs between the cells. Each is moved by a fixed pseudo-random offset of at most a tenth of
  // the lattice spacing (a hash of its position: the same input gives the same points), unless
  // that could take it across another plane's trace (it then stays where it is). A point exactly
  // on another plane's trace (two lattice samples on it: the lattice can meet planes placed on its
  // grid) lies on an edge of its cell, not inside the face whose branching diagram it samples, and
  // its side of that plane is unknown: it is no branching point. One pass over the planes decides
  // both (a moved point stays more than half a jitter off every other plane, so only a point left
  // in place can lie on a trace).
  const double jitter = 0.1 * arr.sample_spacing_mm;
  // Where each point goes (or that it is dropped), in parallel (every plane is tested:
  // multiaxial-3x40's 268 655 points against 120 planes; with their adding 0.21 s on one thread,
  // 0.14 s so); then added in order.
  std::vector<Vec3> placed(branching.size(), Vec3::Zero());
  std::vector<std::uint8_t> dropped(branching.size(), 1);
  tbb::parallel_for(std::size_t(0), branching.size(), [&](std::size_t k) {
    BranchingPoint b = branching[k];
    if (b.plane < 0 || std::size_t(b.plane) >= planes.size() || b.cell < 0) return;
    const Vec3 x = planes[std::size_t(b.plane)].plane.toWorld(b.p);
    bool nearTrace = false, onTrace = false;
    for (std::size_t j = 0; j < planes.size() && !onTrace; ++j) {
      if (int(j) == b.plane) continue;
      const double d = std::abs(planes[j].plane.signedDistance(x));
      onTrace = d <= 1e-9 * (1 + x.norm());
      nearTrace = nearTrace || d < 2 * jitter;
    }
    if (onTrace) return;
    Vec3 at = x;
    if (!nearTrace) {
      std::uint64_t h = std::hash<double>()(b.p.x()) * 0x9e3779b97f4a7c15ULL ^ std::hash<double>()(b.p.y());
      h ^= h >> 31;
      h *= 0xbf58476d1ce4e5b9ULL;
      h ^= h >> 29;
      const double u = double(h & 0xffff) / 65535.0 - 0.5, v = double((h >> 16) & 0xffff) / 65535.0 - 0.5;
      b.p += 2 * jitter * Vec2(u, v);
      at = planes[std::size_t(b.plane)].plane.toWorld(b.p);
    }
    placed[k] = at;
    dropped[k] = 0;
  });
  for (std::size_t k = 0; k < branching.size(); ++k) {
    const BranchingPoint& b = branching[k];
    if (dropped[k]) continue;
    const Vec3& at = placed[k];
    SectionVertex v;
    v.planes = {b.plane, -1, -1};
    v.section = b.section;
    v.kind = SectionVertex::branching;
    // The side of the plane the cell lies on is read from a contour point of the same section
    // bounding that cell; a branching point in a cell no contour point of its plane bounds is
    // dropped.
    v.cells.push_back({b.cell, {0, 0}});
    merger.add(at, v);
  }
}

/// A branching point's side of its plane in each of its cells, as the other points bounding the
/// cell on that plane give it; cells without one are dropped.
void readBranchingSides(SectionVertices& sv) {
  const auto planeCell = [](int plane, int cell) {
    return std::uint64_t(std::uint32_t(plane)) << 32 | std::uint32_t(cell);
  };
  // (plane, cell) -> side, as the points other than branching points give it in id order (the
  // last one's, as a map assigned in that order would hold): a list sorted by (key, order), read
  // in parallel (random-800's map took 2.9 s: 12.6 million entries from its corners alone, 24 each).
  struct SideEntry {
    std::uint64_t key;
    std::uint32_t order;
    int side;
  };
  std::vector<SideEntry> sideOf;
  for (const SectionVertex& v : sv.points)
    if (v.kind != SectionVertex::branching)
      for (const PointCell& c : v.cells)
        for (int k = 0; k < 3; ++k)
          if (const int p = v.planes[std::size_t(k)]; p >= 0)
            sideOf.push_back({planeCell(p, c.cell), std::uint32_t(sideOf.size()), c.side[std::size_t(k)]});
  tbb::parallel_sort(sideOf.begin(), sideOf.end(), [](const SideEntry& a, const SideEntry& b) {
    return a.key != b.key ? a.key < b.key : a.order < b.order;
  });
  std::size_t kept = 0;
  for (std::size_t r = 0; r < sideOf.size(); ++r)
    if (r + 1 == sideOf.size() || sideOf[r + 1].key != sideOf[r].key) sideOf[kept++] = sideOf[r];
  sideOf.resize(kept);
  tbb::parallel_for(std::size_t(0), sv.points.size(), [&](std::size_t id) {
    SectionVertex& v = sv.points[id];
    if (v.kind != SectionVertex::branching) return;
    std::vector<PointCell> known;
    for (PointCell c : v.cells) {
      if (c.side[0] != 0) {
        known.push_back(c);
        continue;
      }
      const std::uint64_t key = planeCell(v.planes[0], c.cell);
      const auto it = std::lower_bound(sideOf.begin(), sideOf.end(), key,
                                       [](const SideEntry& e, std::uint64_t k) { return e.key < k; });
      if (it == sideOf.end() || it->key != key) continue;
      c.side[0] = std::int8_t(it->side);
      known.push_back(c);
    }
    v.cells = std::move(known);
  });
}

/// Branching points must lie inside the sampled section, away from its contour: one between a
/// chord and the true contour would make its triangles external, one next to a contour vertex
/// a sliver. The others lose their cells.
void keepBranchingInsideSampledSections(const std::vector<CuttingPlane>& planes, const SectionArrangement& arr,
                                        SectionVertices& sv) {
  const double margin = 0.5 * arr.sample_spacing_mm;
  // (The section holding the point is bounded by the nearest contour: another section's contour
  // lies beyond its own. Located, not scanned: 0.25 s of multiaxial-3x40's 0.4 s here.)
  std::vector<SectionLocator> located;
  located.reserve(sv.sampled.size());
  for (const std::vector<Section>& s : sv.sampled) located.emplace_back(s);
  tbb::parallel_for(std::size_t(0), sv.points.size(), [&](std::size_t id) {
    SectionVertex& v = sv.points[id];
    if (v.kind != SectionVertex::branching || v.cells.empty()) return;
    const SectionLocator& L = located[std::size_t(v.planes[0])];
    const Vec2 q = planes[std::size_t(v.planes[0])].plane.toPlane(v.x);
    if (!(L.holding(q) >= 0 && L.nearestContour(q).d > margin)) v.cells.clear();
  });
}

}  // namespace

Vec2 planeCoordinates(const SectionVertices& sv, const std::vector<CuttingPlane>& planes, int id, int plane) {
  return planes[std::size_t(plane)].plane.toPlane(sv.points[std::size_t(id)].x);
}

std::vector<int> edgeCells(const SectionVertices& sv, int a, int b, int plane) {
  const SectionVertex& A = sv.points[std::size_t(a)];
  const SectionVertex& B = sv.points[std::size_t(b)];
  const int ia = A.slot(plane), ib = B.slot(plane);
  std::vector<int> out;
  for (int side : {-1, 1}) {
    for (const PointCell& ca : A.cells) {
      if (ca.side[std::size_t(ia)] != side) continue;
      bool found = false;
      for (const PointCell& cb : B.cells)
        if (cb.cell == ca.cell && cb.side[std::size_t(ib)] == side) found = true;
      if (found) {
        out.push_back(ca.cell);
        break;
      }
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

SectionVertices sectionVertices(const std::vector<CuttingPlane>& planes, const SectionArrangement& arr,
                                const std::vector<BranchingPoint>& branching) {
  SectionVertices sv;
  sv.cells = arr.cells;
  VertexMerger merger(sv, 1e-7 * arr.sample_spacing_mm, arr.points.size());
  addRings(planes, arr, merger, sv);
  addCorners(planes, arr, merger, sv);
  mergeTracePairs(sv, arr.sample_spacing_mm);
  // Trace points onto both their planes (after the merges, which key on the computed positions).
  for (SectionVertex& v : sv.points)
    if (v.kind == SectionVertex::trace && !v.cells.empty()) v.x = ontoPlanes(v.x, planes, v.planes);
  addBranchingPoints(planes, arr, branching, merger);
  readBranchingSides(sv);
  resampleSections(sv, planes);
  keepBranchingInsideSampledSections(planes, arr, sv);
  return sv;
}

int splitRingEdge(SectionVertices& sv, const std::vector<CuttingPlane>& planes, std::size_t r, std::size_t k) {
  SampledRing& ring = sv.rings[r];
  const int a = ring.points[k], b = ring.points[(k + 1) % ring.points.size()];
  const CuttingPlane& cp = planes[std::size_t(ring.plane)];
  const Vec2 m = 0.5 * (planeCoordinates(sv, planes, a, ring.plane) + planeCoordinates(sv, planes, b, ring.plane));
  SectionVertex v;
  v.planes = {ring.plane, -1, -1};
  v.section = ring.section;
  v.kind = SectionVertex::conformity;
  const SectionVertex& A = sv.points[std::size_t(a)];
  const int ia = A.slot(ring.plane);
  for (const int c : edgeCells(sv, a, b, ring.plane))
    for (const PointCell& pc : A.cells)
      if (pc.cell == c) v.cells.push_back({c, {pc.side[std::size_t(ia)], 0}});
  v.x = cp.plane.toWorld(m);
  sv.points.push_back(std::move(v));
  const int id = int(sv.points.size()) - 1;
  ring.points.insert(ring.points.begin() + std::ptrdiff_t(k + 1), id);
  return id;
}

void resampleSections(SectionVertices& sv, const std::vector<CuttingPlane>& planes) {
  sv.sampled.assign(planes.size(), {});
  for (std::size_t p = 0; p < planes.size(); ++p) sv.sampled[p].resize(planes[p].sections.size());
  for (const SampledRing& r : sv.rings) {
    Ring ring;
    for (const int id : r.points) ring.push_back(planeCoordinates(sv, planes, id, r.plane));
    Section& s = sv.sampled[std::size_t(r.plane)][std::size_t(r.section)];
    if (r.ring == 0) s.outer = std::move(ring);
    else s.holes.push_back(std::move(ring));
  }
}

}  // namespace xsect
