// Tunnels of one cell's R'' that its sections do not carry, cut (see cell_cycles.h).
#include "geometry/delaunay/cell_cycles.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>

#include "geometry/core/disjoint_sets.h"

namespace xsect {

namespace {

struct Topology {
  long b0 = 0, b1 = 0, b2 = 0;
};

/// The Betti numbers of the simplicial complex of the kept tetrahedra, measured in every cell
/// whose pairs form a cycle and whose kept tetrahedra are not all (see cutCellCycles; on
/// multiaxial-3x40 at most 1 516 of 11 514 cells): faces are counted from the
/// neighbour table (a face inside the set is shared by two kept tetrahedra), components through
/// shared vertices are looked for only when the tetrahedra are not all joined by faces, and the
/// cavities are the groups of other tetrahedra (face-joined) that do not reach the hull.
Topology keptTopology(const CellComplex& c) {
  std::vector<int> vertices;
  std::vector<std::uint64_t> edges;
  std::vector<int> kept;
  long boundaryFaces = 0;
  for (std::size_t t = 0; t < c.v.size(); ++t) {
    if (!c.kept[t]) continue;
    kept.push_back(int(t));
    const std::array<int, 4>& a = c.v[t];
    vertices.insert(vertices.end(), a.begin(), a.end());
    for (const auto& e : kEdges) edges.push_back(edgeKey(a[std::size_t(e[0])], a[std::size_t(e[1])]));
    for (const int o : c.nb[t]) boundaryFaces += o < 0 || !c.kept[std::size_t(o)];
  }
  if (kept.empty()) return {};
  const long T = long(kept.size());
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  const long chi = long(vertices.size()) - long(edges.size()) + (4 * T + boundaryFaces) / 2 - T;
  // Marks the tetrahedra on `kept`'s side face-joined to those on the stack; how many it took.
  std::vector<std::uint8_t> seen(c.v.size(), 0);
  std::vector<int> stack;
  const auto flood = [&](std::uint8_t side) {
    long reached = 0;
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      ++reached;
      for (const int o : c.nb[std::size_t(t)])
        if (o >= 0 && c.kept[std::size_t(o)] == side && !seen[std::size_t(o)]) {
          seen[std::size_t(o)] = 1;
          stack.push_back(o);
        }
    }
    return reached;
  };
  // Components through faces: one means one through vertices too.
  stack.push_back(kept[0]);
  seen[std::size_t(kept[0])] = 1;
  const long reached = flood(1);
  long b0 = 1;
  if (reached < T) {
    DisjointSets sets(vertices.size());
    const auto index = [&](int id) {
      return std::size_t(std::lower_bound(vertices.begin(), vertices.end(), id) - vertices.begin());
    };
    for (const std::uint64_t e : edges) sets.unite(index(int(e >> 32)), index(int(e & 0xffffffffu)));
    b0 = 0;
    for (std::size_t k = 0; k < vertices.size(); ++k) b0 += sets.find(k) == k;
  }
  // Cavities: the other tetrahedra, from those on the hull outwards; what is not reached.
  std::fill(seen.begin(), seen.end(), std::uint8_t(0));
  for (std::size_t t = 0; t < c.v.size(); ++t)
    if (!c.kept[t] && std::any_of(c.nb[t].begin(), c.nb[t].end(), [](int o) { return o < 0; })) {
      seen[t] = 1;
      stack.push_back(int(t));
    }
  flood(0);
  long b2 = 0;
  for (std::size_t t = 0; t < c.v.size(); ++t) {
    if (c.kept[t] || seen[t]) continue;
    ++b2;  // a cavity: mark its whole group
    seen[t] = 1;
    stack.push_back(int(t));
    flood(0);
  }
  return {b0, b0 - chi + b2, b2};
}

/// The footprint of the kept tetrahedra on the cell's faces (their grounded triangles): its
/// components through shared edges and its Euler characteristic. The pieces of two cells meet
/// there, so a cut that changes it trades the cell's tunnel for one through the gluing.
std::pair<long, long> footprintTopology(const CellComplex& c) {
  std::vector<std::array<int, 3>> triangles;
  for (std::size_t t = 0; t < c.v.size(); ++t) {
    if (!c.kept[t] || !c.grounded_faces[t]) continue;
    for (int i = 0; i < 4; ++i) {
      if (!(c.grounded_faces[t] >> i & 1)) continue;
      std::array<int, 3> f{};
      for (int j = 0, m = 0; j < 4; ++j)
        if (j != i) f[std::size_t(m++)] = c.v[t][std::size_t(j)];
      std::sort(f.begin(), f.end());
      triangles.push_back(f);
    }
  }
  std::sort(triangles.begin(), triangles.end());
  triangles.erase(std::unique(triangles.begin(), triangles.end()), triangles.end());
  std::vector<std::pair<std::uint64_t, int>> edges;  // (edge, triangle)
  std::vector<int> vertices;
  for (std::size_t k = 0; k < triangles.size(); ++k) {
    const auto& f = triangles[k];
    vertices.insert(vertices.end(), f.begin(), f.end());
    edges.push_back({edgeKey(f[0], f[1]), int(k)});
    edges.push_back({edgeKey(f[0], f[2]), int(k)});
    edges.push_back({edgeKey(f[1], f[2]), int(k)});
  }
  std::sort(edges.begin(), edges.end());
  std::sort(vertices.begin(), vertices.end());
  const long V = long(std::unique(vertices.begin(), vertices.end()) - vertices.begin());
  DisjointSets sets(triangles.size());
  long E = 0;
  for (std::size_t q = 0; q < edges.size(); ++q) {
    if (q == 0 || edges[q].first != edges[q - 1].first) ++E;
    else sets.unite(std::size_t(edges[q].second), std::size_t(edges[q - 1].second));
  }
  long b0 = 0;
  for (std::size_t k = 0; k < triangles.size(); ++k) b0 += sets.find(k) == k;
  return {b0, V - E + long(triangles.size())};
}

/// The sections (flat ids, ascending, unique) of tetrahedron t's vertices, and the plane of each.
int sectionsOf(const CellComplex& c, std::size_t t, const std::vector<int>& sectionOf,
               const std::vector<SectionVertex>& points, int out[4], int plane[4]) {
  int n = 0;
  for (const int v : c.v[t]) {
    const int s = sectionOf[std::size_t(v)];
    if (s < 0 || std::find(out, out + n, s) != out + n) continue;
    int k = n++;
    for (; k > 0 && out[k - 1] > s; --k) {
      out[k] = out[k - 1];
      plane[k] = plane[k - 1];
    }
    out[k] = s;
    plane[k] = points[std::size_t(v)].planes[0];
  }
  return n;
}

/// Whether tetrahedron t has a vertex in each section of `pair`.
bool joins(const CellComplex& c, std::size_t t, const std::vector<int>& sectionOf, const std::pair<int, int>& pair) {
  bool a = false, b = false;
  for (const int v : c.v[t]) {
    a = a || sectionOf[std::size_t(v)] == pair.first;
    b = b || sectionOf[std::size_t(v)] == pair.second;
  }
  return a && b;
}

double volume(const CellComplex& c, std::size_t t, const std::vector<SectionVertex>& points) {
  const Vec3& a = points[std::size_t(c.v[t][0])].x;
  return std::abs((points[std::size_t(c.v[t][1])].x - a)
                      .dot((points[std::size_t(c.v[t][2])].x - a).cross(points[std::size_t(c.v[t][3])].x - a))) / 6;
}

/// Whether H_C, the pairs of sections on different planes that the kept tetrahedra join, has a
/// cycle: a cell with fewer than three sections, or whose pairs form a forest, is not measured
/// (on multiaxial-3x40, about 200 of its 11518 cells).
bool pairsHaveCycle(const CellComplex& c, const std::vector<int>& sectionOf, const std::vector<SectionVertex>& points) {
  std::vector<std::uint64_t> pairs;
  std::vector<int> ids;
  for (std::size_t t = 0; t < c.v.size(); ++t) {
    if (!c.kept[t]) continue;
    int s[4], plane[4];
    const int n = sectionsOf(c, t, sectionOf, points, s, plane);
    for (int i = 0; i < n; ++i) {
      ids.push_back(s[i]);
      for (int j = i + 1; j < n; ++j)
        if (plane[i] != plane[j]) pairs.push_back(edgeKey(s[i], s[j]));
    }
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  if (ids.size() < 3) return false;
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  DisjointSets sets(ids.size());
  const auto at = [&](int s) { return std::size_t(std::lower_bound(ids.begin(), ids.end(), s) - ids.begin()); };
  for (const std::uint64_t p : pairs) {
    const std::size_t a = sets.find(at(int(p >> 32))), b = sets.find(at(int(p & 0xffffffffu)));
    if (a == b) return true;
    sets.unite(a, b);
  }
  return false;
}

/// H_C with the volume (mm³) of the kept tetrahedra joining each pair.
std::map<std::pair<int, int>, double> joinedPairs(const CellComplex& c, const std::vector<int>& sectionOf,
                                                  const std::vector<SectionVertex>& points) {
  std::map<std::pair<int, int>, double> joined;
  for (std::size_t t = 0; t < c.v.size(); ++t) {
    if (!c.kept[t]) continue;
    int s[4], plane[4];
    const int n = sectionsOf(c, t, sectionOf, points, s, plane);
    if (n < 2) continue;
    const double vol = volume(c, t, points);
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        if (plane[i] != plane[j]) joined[{s[i], s[j]}] += vol;
  }
  return joined;
}

/// The pairs of H_C on a cycle (their sections stay joined without them), by volume, then pair.
std::vector<std::pair<double, std::pair<int, int>>> cyclePairs(const std::map<std::pair<int, int>, double>& joined) {
  std::vector<int> ids;
  for (const auto& [pair, vol] : joined) {
    ids.push_back(pair.first);
    ids.push_back(pair.second);
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  const auto at = [&](int s) { return std::size_t(std::lower_bound(ids.begin(), ids.end(), s) - ids.begin()); };
  std::vector<std::pair<double, std::pair<int, int>>> out;
  DisjointSets all(ids.size());
  for (const auto& [pair, vol] : joined) all.unite(at(pair.first), at(pair.second));
  std::size_t parts = 0;
  for (std::size_t k = 0; k < ids.size(); ++k) parts += all.find(k) == k;
  if (joined.size() + parts <= ids.size()) return out;  // a forest: no cycle
  for (const auto& [pair, vol] : joined) {
    DisjointSets sets(ids.size());
    for (const auto& [other, unused] : joined)
      if (other != pair) sets.unite(at(other.first), at(other.second));
    if (sets.find(at(pair.first)) == sets.find(at(pair.second))) out.push_back({vol, pair});
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

CellCycleCuts cutCellCycles(CellComplex& c, const std::vector<int>& sectionOf,
                            const std::vector<SectionVertex>& points) {
  CellCycleCuts cuts;
  // Every tetrahedron kept but the flat ones (four vertices on one plane, a plane that bounds the
  // cell: they lie in its boundary, between two triangulations of a piece of a face): the kept ones
  // are the triangulation of the convex hull of the cell's points less a collar of part of its
  // boundary, a ball. So it is in most cells (multiaxial-3x40: 9 998 of 11 514, whose measuring
  // took 0.38 s of CPU; 200 random planes through the genus-2 solid: 11 266 of 15 400). Checked
  // before relying on it: every such cell of nine inputs (47 000 cells, conformity enforced) measured
  // (1, 0, 0).
  bool hull = true;
  for (std::size_t t = 0; t < c.v.size() && hull; ++t) hull = c.kept[t] || c.type[t] == TetType::flat;
  if (c.v.empty() || hull || !pairsHaveCycle(c, sectionOf, points)) return cuts;
  Topology now = keptTopology(c);  // before weighing the pairs: a tunnel is rare
  if (now.b1 <= 0) return cuts;
  std::vector<std::pair<double, std::pair<int, int>>> candidates = cyclePairs(joinedPairs(c, sectionOf, points));
  if (candidates.empty()) return cuts;
  const std::pair<long, long> footprint = footprintTopology(c);
  while (now.b1 > 0 && !candidates.empty()) {
    bool cutOne = false;
    for (const auto& candidate : candidates) {
      const std::pair<int, int>& pair = candidate.second;
      std::vector<std::uint8_t> before = c.cycle_cut, keptBefore = c.kept;
      const std::int64_t d1 = c.d1, d2 = c.d2, d3 = c.d3;
      if (c.cycle_cut.empty()) c.cycle_cut.assign(c.v.size(), 0);
      for (std::size_t t = 0; t < c.v.size(); ++t)
        if (joins(c, t, sectionOf, pair)) c.cycle_cut[t] = 1;
      pruneCell(c);
      const Topology after = keptTopology(c);
      if (after.b1 < now.b1 && after.b0 <= now.b0 && after.b2 <= now.b2 && footprintTopology(c) == footprint) {
        cuts.tunnels += int(now.b1 - after.b1);
        now = after;
        ++cuts.pairs;
        cutOne = true;
        break;
      }
      // Undone (pruneCell depends on its flags only): no tunnel cut, or a part, a cavity, the
      // footprint changed.
      c.cycle_cut = std::move(before);
      c.kept = std::move(keptBefore);
      c.d1 = d1;
      c.d2 = d2;
      c.d3 = d3;
    }
    if (!cutOne) break;
    candidates = cyclePairs(joinedPairs(c, sectionOf, points));
  }
  for (std::size_t t = 0; t < c.cycle_cut.size(); ++t)
    cuts.tetrahedra += c.cycle_cut[t] && c.type[t] != TetType::flat && !c.external[t] && !c.unjoined[t];
  return cuts;
}

}  // namespace xsect
