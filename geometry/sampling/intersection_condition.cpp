// The Intersection Condition shown on the data, per cell (see intersection_condition.h).
#include "geometry/sampling/intersection_condition.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include "geometry/core/disjoint_sets.h"
#include "geometry/core/section_ids.h"

namespace xsect {

namespace {

/// Points within this many sample spacings are taken as connected (the lattice's diagonal is √2).
constexpr double kLink = 1.5;

/// A hash grid over plane coordinates with cells of the link distance.
class PlaneGrid {
 public:
  PlaneGrid(const std::vector<Vec2>& pts, double link) : pts_(pts), link_(link) {
    for (std::size_t i = 0; i < pts.size(); ++i) cells_[keyOf(pts[i])].push_back(int(i));
  }
  /// Calls f(j) for every point j within the link distance of x.
  template <class F>
  void near(const Vec2& x, F f) const {
    const long long ix = std::llround(std::floor(x.x() / link_)), iy = std::llround(std::floor(x.y() / link_));
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy) {
        const auto it = cells_.find(pack(ix + dx, iy + dy));
        if (it == cells_.end()) continue;
        for (const int j : it->second)
          if ((pts_[std::size_t(j)] - x).squaredNorm() <= link_ * link_) f(j);
      }
  }

 private:
  static long long pack(long long ix, long long iy) { return ix * 0x100000007LL + iy; }
  long long keyOf(const Vec2& p) const {
    return pack(std::llround(std::floor(p.x() / link_)), std::llround(std::floor(p.y() / link_)));
  }
  const std::vector<Vec2>& pts_;
  double link_;
  std::unordered_map<long long, std::vector<int>> cells_;
};

/// Connected components of points under the link distance: labels 0.. in the order first met.
int cluster(const std::vector<Vec2>& pts, double link, std::vector<int>* label) {
  const PlaneGrid grid(pts, link);
  DisjointSets sets(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) grid.near(pts[i], [&](int j) { sets.unite(i, std::size_t(j)); });
  label->assign(pts.size(), -1);
  std::vector<int> of(pts.size(), -1);
  int n = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const std::size_t r = sets.find(i);
    if (of[r] < 0) of[r] = n++;
    (*label)[i] = of[r];
  }
  return n;
}

/// Cells bounded by a piece with a hole: a hole ring that no plane separates lies inside one face,
/// of the cells on both sides of its plane.
std::vector<char> cellsWithHoles(const std::vector<CuttingPlane>& planes, const SectionArrangement& arr) {
  std::vector<char> hole(std::size_t(std::max(arr.cells, 0)), 0);
  // The arrangement's points of each (plane, section), in order.
  std::map<std::pair<int, int>, std::pair<std::size_t, std::size_t>> range;
  for (std::size_t q = 0; q < arr.points.size(); ++q) {
    auto& r = range.try_emplace({arr.points[q].plane, arr.points[q].section}, q, q).first->second;
    r.second = q + 1;
  }
  for (std::size_t i = 0; i < planes.size(); ++i)
    for (std::size_t s = 0; s < planes[i].sections.size(); ++s)
      for (const Ring& h : planes[i].sections[s].holes) {
        if (h.empty()) continue;
        std::vector<Vec3> w;
        Vec3 centre = Vec3::Zero();
        for (const Vec2& p : h) w.push_back(planes[i].plane.toWorld(p)), centre += w.back();
        centre /= double(w.size());
        double radius = 0;
        for (const Vec3& x : w) radius = std::max(radius, (x - centre).norm());
        bool separated = false;
        for (std::size_t j = 0; j < planes.size() && !separated; ++j) {
          if (j == i || std::abs(planes[j].plane.signedDistance(centre)) > radius * (1 + 1e-9) + 1e-12) continue;
          bool neg = false, pos = false;
          for (const Vec3& x : w) {
            const double d = planes[j].plane.signedDistance(x);
            neg = neg || d <= 0;
            pos = pos || d >= 0;
          }
          separated = neg && pos;
        }
        if (separated) continue;
        const auto it = range.find({int(i), int(s)});
        if (it == range.end()) continue;
        for (std::size_t q = it->second.first; q < it->second.second; ++q) {
          const SectionPoint& sp = arr.points[q];
          if (sp.kind != SectionPoint::vertex || sp.p != h.front()) continue;
          for (const int c : sp.cell)
            if (c >= 0) hole[std::size_t(c)] = 1;
          break;
        }
      }
  return hole;
}

}  // namespace

IntersectionConditionCheck checkIntersectionCondition(const std::vector<CuttingPlane>& planes,
                                                      const SectionArrangement& arr,
                                                      const std::vector<std::int32_t>& lift_section,
                                                      const std::vector<float>& lift_length_mm) {
  IntersectionConditionCheck out;
  const std::size_t nCells = std::size_t(std::max(arr.cells, 0));
  out.shown.assign(nCells, 0);
  if (lift_section.size() != 2 * arr.points.size() || lift_length_mm.size() != lift_section.size()) return out;
  const double link = kLink * arr.sample_spacing_mm;
  const SectionIds ids(planes);
  std::vector<int> planeOf(std::size_t(ids.count()), -1);
  for (std::size_t i = 0; i < planes.size(); ++i)
    for (std::size_t s = 0; s < planes[i].sections.size(); ++s) planeOf[std::size_t(ids.of(int(i), int(s)))] = int(i);
  const std::vector<char> hole = cellsWithHoles(planes, arr);

  // The points bounding each cell (point, side of its own plane), cell by cell.
  struct Entry {
    int point, side;
  };
  std::vector<std::size_t> first(nCells + 1, 0);
  const auto forEachCell = [&](auto f) {
    for (std::size_t q = 0; q < arr.points.size(); ++q)
      for (int k = 0; k < 2; ++k) {
        const SectionPoint& sp = arr.points[q];
        if (sp.cell[std::size_t(k)] >= 0) f(std::size_t(sp.cell[std::size_t(k)]), Entry{int(q), k});
        if (sp.cell_alt[std::size_t(k)] >= 0) f(std::size_t(sp.cell_alt[std::size_t(k)]), Entry{int(q), k});
      }
  };
  forEachCell([&](std::size_t c, const Entry&) { ++first[c + 1]; });
  for (std::size_t c = 0; c < nCells; ++c) first[c + 1] += first[c];
  std::vector<Entry> entries(first.back());
  {
    std::vector<std::size_t> fill(first.begin(), first.end() - 1);
    forEachCell([&](std::size_t c, const Entry& e) { entries[fill[c]++] = e; });
  }

  enum Outcome : std::uint8_t { shown, holes, cycles, unlocated };
  std::vector<std::uint8_t> outcome(nCells, shown);
  tbb::parallel_for(std::size_t(0), nCells, [&](std::size_t c) {
    if (hole[c]) {
      outcome[c] = holes;
      return;
    }
    // Group the cell's points by section (a cell lies on one side of each plane).
    std::vector<Entry> es(entries.begin() + std::ptrdiff_t(first[c]), entries.begin() + std::ptrdiff_t(first[c + 1]));
    const auto sectionId = [&](const Entry& e) {
      const SectionPoint& sp = arr.points[std::size_t(e.point)];
      return ids.of(sp.plane, sp.section);
    };
    std::sort(es.begin(), es.end(), [&](const Entry& a, const Entry& b) {
      const int sa = sectionId(a), sb = sectionId(b);
      return sa != sb ? sa < sb : a.point < b.point;
    });
    struct Group {
      int section = -1;
      std::size_t begin = 0, end = 0;
      std::vector<Vec2> pts;
      std::vector<int> piece;  ///< per point: global piece index within the cell
    };
    std::vector<Group> groups;
    std::unordered_map<int, int> groupOf;
    for (std::size_t i = 0; i < es.size(); ++i) {
      const int s = sectionId(es[i]);
      if (groups.empty() || groups.back().section != s) {
        groupOf[s] = int(groups.size());
        groups.push_back({s, i, i, {}, {}});
      }
      groups.back().end = i + 1;
      groups.back().pts.push_back(arr.points[std::size_t(es[i].point)].p);
    }
    int pieces = 0;
    std::vector<PlaneGrid> grids;
    grids.reserve(groups.size());
    for (Group& g : groups) {
      const int n = cluster(g.pts, link, &g.piece);
      for (int& p : g.piece) p += pieces;
      pieces += n;
      grids.emplace_back(g.pts, link);
    }
    // Per (piece, piece it lifts into): the points whose lift lands there, in plane coordinates.
    std::map<std::pair<int, int>, std::vector<Vec2>> hits;
    for (const Group& g : groups)
      for (std::size_t i = g.begin; i < g.end; ++i) {
        const Entry& e = es[i];
        const SectionPoint& sp = arr.points[std::size_t(e.point)];
        const int b = lift_section[2 * std::size_t(e.point) + std::size_t(e.side)];
        if (sp.kind == SectionPoint::trace || b < 0) continue;
        const auto it = groupOf.find(b);
        if (it == groupOf.end()) {
          outcome[c] = unlocated;
          return;
        }
        const Plane& A = planes[std::size_t(sp.plane)].plane;
        const Vec3 y = A.toWorld(sp.p) + double(lift_length_mm[2 * std::size_t(e.point) + std::size_t(e.side)]) *
                                              (e.side == 0 ? -1.0 : 1.0) * A.normal;
        const Group& gb = groups[std::size_t(it->second)];
        const Vec2 yb = planes[std::size_t(planeOf[std::size_t(b)])].plane.toPlane(y);
        int nearest = -1;
        double best = 0;
        grids[std::size_t(it->second)].near(yb, [&](int j) {
          const double d = (gb.pts[std::size_t(j)] - yb).squaredNorm();
          if (nearest < 0 || d < best || (d == best && j < nearest)) nearest = j, best = d;
        });
        if (nearest < 0) {
          outcome[c] = unlocated;
          return;
        }
        hits[{g.piece[i - g.begin], gb.piece[std::size_t(nearest)]}].push_back(sp.p);
      }
    // One edge per component of each lift intersection, the larger count of its two sides.
    std::map<std::pair<int, int>, int> edges;
    std::vector<int> label;
    for (const auto& [pair, pts] : hits) {
      if (pair.first == pair.second) continue;  // a piece lifting into itself: not an intersection
      const int n = cluster(pts, link, &label);
      int& m = edges[{std::min(pair.first, pair.second), std::max(pair.first, pair.second)}];
      m = std::max(m, n);
    }
    DisjointSets sets{std::size_t(pieces)};
    int count = 0, components = pieces;
    for (const auto& [pair, n] : edges) {
      count += n;
      if (sets.find(std::size_t(pair.first)) != sets.find(std::size_t(pair.second))) --components;
      sets.unite(std::size_t(pair.first), std::size_t(pair.second));
    }
    if (count != pieces - components) outcome[c] = cycles;
  });
  for (std::size_t c = 0; c < nCells; ++c) {
    out.shown[c] = outcome[c] == shown;
    out.cells_with_holes += outcome[c] == holes;
    out.cells_with_cycles += outcome[c] == cycles;
    out.cells_unlocated += outcome[c] == unlocated;
  }
  return out;
}

}  // namespace xsect
