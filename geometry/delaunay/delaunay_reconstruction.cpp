// Method 3: cells, conformity, pruning, gluing and the repair of singularities (see
// delaunay_reconstruction.h).
#include "geometry/delaunay/delaunay_reconstruction.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "geometry/core/disjoint_sets.h"
#include "geometry/core/section_ids.h"
#include "geometry/delaunay/cell_complex.h"
#include "geometry/delaunay/plane_gluing.h"
#include "geometry/delaunay/section_vertices.h"

namespace xsect {

namespace {

/// The number of faces on each edge (edgeKey) of `faces`.
std::unordered_map<std::uint64_t, int> edgeUses(const std::vector<std::array<int, 3>>& faces) {
  std::unordered_map<std::uint64_t, int> uses;
  for (const auto& f : faces)
    for (int e = 0; e < 3; ++e) ++uses[edgeKey(f[std::size_t(e)], f[std::size_t((e + 1) % 3)])];
  return uses;
}

/// Rounds of contour splitting for Delaunay conformity; each halves the offending edges.
constexpr int kConformityRounds = 8;

struct CellSetup {
  std::vector<std::vector<int>> points;                 ///< per cell
  std::vector<std::vector<std::uint64_t>> contour;      ///< per cell: its contour edges
};

CellSetup cellSetup(const SectionVertices& sv) {
  CellSetup s;
  s.points.resize(std::size_t(sv.cells));
  s.contour.resize(std::size_t(sv.cells));
  for (std::size_t id = 0; id < sv.points.size(); ++id)
    for (const PointCell& c : sv.points[id].cells)
      if (c.cell >= 0 && c.cell < sv.cells) s.points[std::size_t(c.cell)].push_back(int(id));
  return s;
}

void addContourEdges(const SectionVertices& sv, CellSetup& s) {
  for (auto& e : s.contour) e.clear();
  for (const SampledRing& r : sv.rings)
    for (std::size_t k = 0; k < r.points.size(); ++k) {
      const int a = r.points[k], b = r.points[(k + 1) % r.points.size()];
      for (const int c : edgeCells(sv, a, b, r.plane)) s.contour[std::size_t(c)].push_back(edgeKey(a, b));
    }
}

/// Whether the points all lie on one plane (no tetrahedron of D0 could be kept).
bool onOnePlane(const SectionVertices& sv, const std::vector<int>& ids) {
  if (ids.size() < 4) return true;
  for (const int p : sv.points[std::size_t(ids[0])].planes) {
    if (p < 0) continue;
    bool all = true;
    for (const int id : ids) all = all && sv.points[std::size_t(id)].on(p);
    if (all) return true;
  }
  return false;
}

/// Outward triples of a positively oriented tetrahedron: the face opposite vertex i.
constexpr int kOutward[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

struct CellBoundary {
  std::vector<std::array<int, 3>> faces;                         ///< non-grounded, outward
  std::vector<std::tuple<int, int, std::array<int, 3>>> ground;  ///< (plane, side 0/1, triangle)
  std::vector<std::pair<int, std::array<int, 2>>> rims;          ///< (plane, edge)
};

int sideOf(const SectionVertices& sv, int id, int cell, int plane) {
  const SectionVertex& v = sv.points[std::size_t(id)];
  const int k = v.slot(plane);
  for (const PointCell& c : v.cells)
    if (c.cell == cell) return c.side[std::size_t(k)] > 0 ? 1 : 0;
  return 0;
}

CellBoundary cellBoundary(const CellComplex& c, const SectionVertices& sv) {
  CellBoundary b;
  for (std::size_t t = 0; t < c.v.size(); ++t) {
    if (!c.kept[t]) continue;
    for (int i = 0; i < 4; ++i) {
      const int o = c.nb[t][std::size_t(i)];
      if (o >= 0 && c.kept[std::size_t(o)]) continue;
      const std::array<int, 3> f{c.v[t][std::size_t(kOutward[i][0])], c.v[t][std::size_t(kOutward[i][1])],
                                 c.v[t][std::size_t(kOutward[i][2])]};
      const int p = commonPlane(sv, f.data(), 3);
      if (p >= 0) {
        b.ground.push_back({p, sideOf(sv, f[0], c.cell, p), f});
        continue;
      }
      b.faces.push_back(f);
      for (int e = 0; e < 3; ++e) {
        const int ab[2] = {f[std::size_t(e)], f[std::size_t((e + 1) % 3)]};
        const int q = commonPlane(sv, ab, 2);
        if (q >= 0) b.rims.push_back({q, {std::min(ab[0], ab[1]), std::max(ab[0], ab[1])}});
      }
    }
  }
  return b;
}

/// Splits faces at T-junctions: where a face's edge a→b is in an odd number of faces while a face
/// on the other side leaves b towards a point m inside the segment (points of a trace line shared
/// by the cells' triangulations and the plane's, collinear up to rounding; the plane's constraints
/// crossing), the face (a, b, c) becomes (a, m, c) and (m, b, c); the next pass splits (a, m, c)
/// again where several such points lie on the segment. Repeats until no such edge remains.
void splitTJunctions(std::vector<std::array<int, 3>>& faces, const std::function<Vec3(int)>& at) {
  for (int pass = 0; pass < 16; ++pass) {
    std::unordered_map<std::uint64_t, int> uses = edgeUses(faces);
    std::unordered_map<int, std::vector<int>> from;  // directed once-used edges a -> b
    for (const auto& f : faces)
      for (int e = 0; e < 3; ++e) {
        const int a = f[std::size_t(e)], b = f[std::size_t((e + 1) % 3)];
        if (uses[edgeKey(a, b)] % 2 == 1) from[a].push_back(b);
      }
    bool changed = false;
    std::vector<std::array<int, 3>> next;
    next.reserve(faces.size());
    for (const auto& f : faces) {
      bool split = false;
      for (int e = 0; e < 3 && !split; ++e) {
        const int a = f[std::size_t(e)], b = f[std::size_t((e + 1) % 3)], c = f[std::size_t((e + 2) % 3)];
        if (uses[edgeKey(a, b)] % 2 == 0) continue;
        const auto it = from.find(b);
        if (it == from.end()) continue;
        const Vec3 A = at(a), B = at(b);
        const double len = (B - A).norm();
        for (const int m : it->second) {
          if (m == a || m == c) continue;  // c on [a, b]: a face of no area, not a T-junction
          const Vec3 M = at(m);
          const double t = (M - A).dot(B - A) / (len * len);
          if (!(t > 0 && t < 1) || (A + t * (B - A) - M).norm() > 1e-6 * len) continue;
          next.push_back({a, m, c});
          next.push_back({m, b, c});
          split = true;
          break;
        }
      }
      if (!split) next.push_back(f);
      changed = changed || split;
    }
    faces.swap(next);
    if (!changed) return;
  }
}

/// Welds boundary vertices nearer than `tolerance` (a contour crossing sampled on two planes and
/// a corner of three planes can nearly coincide where the planes meet at the surface): in each
/// cluster the point on the most planes (`planesOf`; then the smallest id) takes the others that
/// lie on none but its planes (`covers`), so that no point leaves a plane it lies on; triangles
/// that lose a vertex go, and pairs of triangles on the same three vertices with opposite
/// orientations cancel. Returns the vertices welded.
int weldNearVertices(std::vector<std::array<int, 3>>& faces, const std::vector<Vec3>& positions, double tolerance,
                     const std::function<int(int)>& planesOf, const std::function<bool(int, int)>& covers) {
  std::vector<int> used;
  for (const auto& f : faces) used.insert(used.end(), f.begin(), f.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::unordered_map<std::uint64_t, std::vector<int>> grid;
  const auto cellOf = [&](const Vec3& x, int dx, int dy, int dz) {
    const auto c = [&](double v, int d) { return std::uint64_t(std::int64_t(std::floor(v / tolerance)) + d) & 0x1fffff; };
    return (c(x.x(), dx) << 42) | (c(x.y(), dy) << 21) | c(x.z(), dz);
  };
  for (const int id : used) grid[cellOf(positions[std::size_t(id)], 0, 0, 0)].push_back(id);
  std::unordered_map<int, int> to;
  DisjointSets sets(used.size());
  std::unordered_map<int, std::size_t> slot;
  for (std::size_t k = 0; k < used.size(); ++k) slot[used[k]] = k;
  for (const int id : used) {
    const Vec3& x = positions[std::size_t(id)];
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find(cellOf(x, dx, dy, dz));
          if (it == grid.end()) continue;
          for (const int other : it->second)
            if (other != id && (positions[std::size_t(other)] - x).norm() < tolerance) sets.unite(slot[id], slot[other]);
        }
  }
  std::unordered_map<std::size_t, int> best;  // cluster -> representative
  for (std::size_t k = 0; k < used.size(); ++k) {
    const auto it = best.find(sets.find(k));
    if (it == best.end() || planesOf(used[k]) > planesOf(it->second)) best[sets.find(k)] = used[k];
  }
  int welded = 0;
  for (std::size_t k = 0; k < used.size(); ++k) {
    const int root = best[sets.find(k)];
    const bool weld = root != used[k] && covers(root, used[k]);
    welded += weld;
    to[used[k]] = weld ? root : used[k];
  }
  if (welded == 0) return 0;
  std::map<std::array<int, 3>, std::vector<std::size_t>> byVertices;
  std::vector<std::array<int, 3>> kept;
  for (auto f : faces) {
    for (int& v : f) v = to[v];
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) continue;
    kept.push_back(f);
  }
  // Opposite duplicates cancel.
  std::map<std::array<int, 3>, int> signOf;
  for (const auto& f : kept) {
    std::array<int, 3> key = f;
    const int m = int(std::min_element(key.begin(), key.end()) - key.begin());
    std::rotate(key.begin(), key.begin() + m, key.end());
    const bool flipped = key[1] > key[2];
    if (flipped) std::swap(key[1], key[2]);
    signOf[key] += flipped ? -1 : 1;
  }
  faces.clear();
  for (const auto& [key, n] : signOf) {
    for (int k = 0; k < n; ++k) faces.push_back(key);
    for (int k = 0; k < -n; ++k) faces.push_back({key[0], key[2], key[1]});
  }
  return welded;
}

/// Closes each hole bounded by three or four directed edges a→b→c(→d)→a that are each in an odd
/// number of faces and whose vertices all lie on one plane (`onOnePlane`), with the reversed cycle,
/// unless a face on three of its vertices exists (a lone triangle is its own cycle: its reverse
/// would only hide it as a sheet of no volume). A quadrilateral is split along the diagonal that
/// is no edge of the mesh yet and whose two triangles face the same way (a - c when both do). An
/// odd edge closes at most one hole. Returns the holes closed.
int closeFlatHoles(std::vector<std::array<int, 3>>& faces, const std::vector<Vec3>& positions,
                   const std::function<bool(const std::vector<int>&)>& onOnePlane) {
  std::set<std::array<int, 3>> existing;
  for (std::array<int, 3> f : faces) {
    std::sort(f.begin(), f.end());
    existing.insert(f);
  }
  const auto exists = [&](int a, int b, int c) {
    std::array<int, 3> t{a, b, c};
    std::sort(t.begin(), t.end());
    return existing.count(t) > 0;
  };
  std::unordered_map<std::uint64_t, int> uses = edgeUses(faces);
  std::map<int, std::vector<int>> next;  // directed half-edges of the odd edges, a -> b
  for (const auto& f : faces)
    for (int e = 0; e < 3; ++e) {
      const int a = f[std::size_t(e)], b = f[std::size_t((e + 1) % 3)];
      if (uses[edgeKey(a, b)] % 2 == 1) next[a].push_back(b);
    }
  const std::vector<int> none;
  const auto after = [&](int a) -> const std::vector<int>& {
    const auto it = next.find(a);
    return it == next.end() ? none : it->second;
  };
  // Cycles from their smallest vertex (each found once), triangles before quadrilaterals.
  std::vector<std::vector<int>> cycles;
  for (const std::size_t length : {3, 4})
    for (const auto& [a, bs] : next)
      for (const int b : bs)
        for (const int c : after(b)) {
          if (c == a || b < a || c < a) continue;
          if (length == 3) {
            const auto& cs = after(c);
            if (std::find(cs.begin(), cs.end(), a) != cs.end() && !exists(a, b, c)) cycles.push_back({a, b, c});
            continue;
          }
          for (const int d : after(c)) {
            const auto& ds = after(d);
            if (d == a || d == b || d < a || std::find(ds.begin(), ds.end(), a) == ds.end()) continue;
            if (!exists(a, b, c) && !exists(a, c, d) && !exists(a, b, d) && !exists(b, c, d)) cycles.push_back({a, b, c, d});
          }
        }
  const auto normal = [&](int a, int b, int c) {
    const Vec3& o = positions[std::size_t(a)];
    return Vec3((positions[std::size_t(b)] - o).cross(positions[std::size_t(c)] - o));
  };
  std::set<std::uint64_t> closedEdges;
  int closed = 0;
  for (std::vector<int> h : cycles) {
    bool free = true;
    for (std::size_t k = 0; k < h.size(); ++k) free = free && !closedEdges.count(edgeKey(h[k], h[(k + 1) % h.size()]));
    if (!free || !onOnePlane(h)) continue;
    for (std::size_t k = 0; k < h.size(); ++k) closedEdges.insert(edgeKey(h[k], h[(k + 1) % h.size()]));
    if (h.size() == 4) {  // the reversed triangles (a, d, c), (a, c, b) or (b, a, d), (b, d, c)
      const bool acFree = !uses.count(edgeKey(h[0], h[2])), bdFree = !uses.count(edgeKey(h[1], h[3]));
      const bool acFlat = normal(h[0], h[3], h[2]).dot(normal(h[0], h[2], h[1])) > 0;
      const bool bdFlat = normal(h[1], h[0], h[3]).dot(normal(h[1], h[3], h[2])) > 0;
      if (!(acFree && acFlat) && bdFree && bdFlat) std::rotate(h.begin(), h.begin() + 1, h.end());
    }
    for (std::size_t k = h.size() - 1; k >= 2; --k) faces.push_back({h[0], h[k], h[k - 1]});
    ++closed;
  }
  return closed;
}

/// Drops each component of the boundary (faces joined through shared vertices) whose mean
/// thickness 3|V| / A (V its signed volume about one of its points, A its area) is below
/// `thickness`: it bounds no volume. Measured: a sliver tetrahedron (four section-vertices on
/// different planes but nearly coplanar) that opening the pinches parted from the solid, or such a
/// void; a flat sheet lying twice on a plane with opposite orientations (V = 4e-16 mm³ for
/// A = 0.4 mm²); two slivers along nearly collinear points of a plane's triangulation (A = 5e-4 mm²,
/// open). Returns the components dropped.
int dropFlatShells(std::vector<std::array<int, 3>>& faces, const std::vector<Vec3>& positions, double thickness) {
  DisjointSets sets(positions.size());
  for (const auto& f : faces) {
    sets.unite(std::size_t(f[0]), std::size_t(f[1]));
    sets.unite(std::size_t(f[1]), std::size_t(f[2]));
  }
  std::unordered_map<std::size_t, std::array<double, 2>> shell;  // root -> (6 V, 2 A)
  for (const auto& f : faces) {
    const std::size_t root = sets.find(std::size_t(f[0]));
    const Vec3& o = positions[root];  // a point of the shell: no cancellation of large terms
    const Vec3 a = positions[std::size_t(f[0])] - o, b = positions[std::size_t(f[1])] - o, c = positions[std::size_t(f[2])] - o;
    auto& s = shell[root];
    s[0] += a.dot(b.cross(c));
    s[1] += (b - a).cross(c - a).norm();
  }
  std::unordered_set<std::size_t> flat;
  for (const auto& [root, s] : shell)
    if (std::abs(s[0]) < thickness * s[1]) flat.insert(root);  // 3|V|/A = |6V| / (2A)
  if (flat.empty()) return 0;
  faces.erase(std::remove_if(faces.begin(), faces.end(),
                             [&](const std::array<int, 3>& f) { return flat.count(sets.find(std::size_t(f[0]))) > 0; }),
              faces.end());
  return int(flat.size());
}

/// Pairs of faces (indices) across an edge: the faces of one sheet there.
using FacePairs = std::vector<std::array<int, 2>>;

struct OpenedPinches {
  int edges = 0;       ///< edges in 4, 6, ... faces whose sheets were separated
  int vertices = 0;    ///< vertices given more than one copy
};

/// Resolves the pinches of the boundary into a 2-manifold. Where 2k > 2 faces meet at an edge
/// (solid wedges touching along it: around a branching line inside a terminal section, Fig. 3.14,
/// or where the pieces of two cells meet on a trace), the faces are paired across the empty
/// wedges, so that the wedges stay joined along the edge, as Def. 50 counts a shell whose runs all
/// reach the section. Then every vertex gets one copy per umbrella (the faces around it joined
/// through such pairs): pieces touching at a single point are separate.
/// An edge that joining leaves singular at both ends (a branching line crossing a section from
/// contour to contour as one Delaunay edge, with no point inside the section to part the sheets
/// at) is split at its midpoint (a point of the edge: the surface does not move; for a grounded
/// edge, inside the section, Def. 47) and the pass repeated once (`splitting` false): the
/// midpoint's copies part the flat sheet from the wedges' as the thickened plane of Fig. 3.8b
/// would, and the wedges stay joined (R'' is their union). Only an edge still singular then is
/// paired apart.
/// `given`, `givenChoices`: face pairs and the two pairings of singular edges fixed in advance
/// (the split pass's; see there), used as they are instead of pairs by angle.
OpenedPinches openPinches(std::vector<std::array<int, 3>>& faces, std::vector<Vec3>& positions, bool splitting = true,
                          const std::unordered_map<std::uint64_t, FacePairs>& given = {},
                          const std::map<std::uint64_t, std::array<FacePairs, 2>>& givenChoices = {}) {
  OpenedPinches out;
  // Per undirected edge: its faces, with +1 when the face runs from the smaller id to the larger.
  std::unordered_map<std::uint64_t, std::vector<std::pair<int, int>>> around;
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int e = 0; e < 3; ++e) {
      const int a = faces[f][std::size_t(e)], b = faces[f][std::size_t((e + 1) % 3)];
      around[edgeKey(a, b)].push_back({int(f), a < b ? 1 : -1});
    }
  // Face pairs across each edge (the faces of one sheet there). At an edge in 2k > 2 faces, sorted
  // by angle around it, two pairings alternate: across the empty wedges (`join`, preferred) and
  // across the solid wedges (`apart`).
  std::unordered_map<std::uint64_t, FacePairs> pairs;
  std::map<std::uint64_t, std::array<FacePairs, 2>> choices;  // singular edges
  std::vector<std::uint64_t> keys;
  for (const auto& [key, list] : around) keys.push_back(key);
  std::sort(keys.begin(), keys.end());
  for (const std::uint64_t key : keys) {
    const auto& list = around[key];
    if (const auto g = given.find(key); g != given.end()) {
      pairs[key] = g->second;
      continue;
    }
    if (list.size() == 2) {
      pairs[key].push_back({list[0].first, list[1].first});
      continue;
    }
    if (list.size() % 2) continue;  // an open edge: left as it is (counted by the caller)
    ++out.edges;
    if (const auto g = givenChoices.find(key); g != givenChoices.end()) {
      choices[key] = g->second;
      continue;
    }
    const int a = int(key >> 32), b = int(key & 0xffffffffu);
    const Vec3 A = positions[std::size_t(a)], d = (positions[std::size_t(b)] - A).normalized();
    Vec3 u = Vec3::Zero();
    std::vector<std::pair<double, std::pair<int, int>>> byAngle;
    for (const auto& [f, dir] : list) {
      int c = -1;
      for (const int x : faces[std::size_t(f)])
        if (x != a && x != b) c = x;
      Vec3 w = positions[std::size_t(c)] - A;
      w -= w.dot(d) * d;
      if (u.isZero()) u = w.normalized();
      byAngle.push_back({std::atan2(d.cross(u).dot(w), u.dot(w)), {f, dir}});
    }
    std::sort(byAngle.begin(), byAngle.end());
    // A face running a → b (a < b) has the solid just below its angle, one running b → a just
    // above: an empty wedge follows a +1 face counter-clockwise, a solid wedge a -1 face. Faces at
    // equal angles (coplanar up to rounding) may come in either order: each face of the leading
    // sign takes the first unpaired face of the other sign after it.
    const std::size_t n = byAngle.size();
    auto& two = choices[key];
    for (int c = 0; c < 2; ++c) {
      const int lead = c == 0 ? 1 : -1;
      std::vector<char> taken(n, 0);
      for (std::size_t k = 0; k < n; ++k) {
        if (byAngle[k].second.second != lead) continue;
        for (std::size_t j = 1; j < n; ++j) {
          const std::size_t q = (k + j) % n;
          if (taken[q] || byAngle[q].second.second == lead) continue;
          taken[q] = 1;
          two[std::size_t(c)].push_back({byAngle[k].second.first, byAngle[q].second.first});
          break;
        }
      }
    }
  }
  std::unordered_map<int, std::vector<int>> facesAt;
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (const int v : faces[f]) facesAt[v].push_back(int(f));
  std::vector<int> vertices;
  for (const auto& [v, list] : facesAt) vertices.push_back(v);
  std::sort(vertices.begin(), vertices.end());
  // Umbrellas: faces around each vertex joined through the pairs of the edges at the vertex.
  std::map<std::uint64_t, int> chosen;  // singular edge -> 0 (join) or 1 (apart)
  for (const auto& [key, two] : choices) chosen[key] = 0;
  const auto pairsAt = [&](std::uint64_t key) -> const FacePairs* {
    const auto c = chosen.find(key);
    if (c != chosen.end()) return &choices[key][std::size_t(c->second)];
    const auto it = pairs.find(key);
    return it == pairs.end() ? nullptr : &it->second;
  };
  const auto umbrellasOf = [&](int v) {
    const std::vector<int>& list = facesAt[v];
    std::unordered_map<int, std::size_t> at;
    for (std::size_t k = 0; k < list.size(); ++k) at[list[k]] = k;
    DisjointSets umbrella(list.size());
    for (const int f : list)
      for (const int x : faces[std::size_t(f)]) {
        if (x == v) continue;
        const auto* ps = pairsAt(edgeKey(v, x));
        if (!ps) continue;
        for (const auto& pr : *ps) {
          const auto i = at.find(pr[0]), j = at.find(pr[1]);
          if (i != at.end() && j != at.end()) umbrella.unite(i->second, j->second);
        }
      }
    std::unordered_map<int, std::size_t> rootOf;
    for (std::size_t k = 0; k < list.size(); ++k) rootOf[list[k]] = umbrella.find(k);
    return rootOf;
  };
  // A singular edge stays singular when, at both its ends, all its faces fall in one umbrella:
  // such an edge is split at its midpoint (see above), or, on the second pass, paired the other
  // way (which then splits an end's umbrella).
  std::vector<std::uint64_t> bisect;
  for (const auto& [key, two] : choices) {
    const int a = int(key >> 32), b = int(key & 0xffffffffu);
    const auto split = [&](int v) {
      const auto roots = umbrellasOf(v);
      std::set<std::size_t> seen;
      for (const auto& pr : *pairsAt(key)) seen.insert(roots.at(pr[0]));
      return seen.size() > 1;
    };
    if (split(a) || split(b)) continue;
    if (splitting) bisect.push_back(key);
    else chosen[key] = 1;
  }
  if (!bisect.empty()) {
    const int firstMidpoint = int(positions.size());
    std::unordered_map<std::uint64_t, int> midpoint;
    for (const std::uint64_t key : bisect) {
      midpoint[key] = int(positions.size());
      positions.push_back(0.5 * (positions[std::size_t(key >> 32)] + positions[std::size_t(key & 0xffffffffu)]));
    }
    // Split faces, each remembering the face it came from (a face may hold two such edges).
    std::vector<std::array<int, 3>> next;
    std::vector<int> origin;
    std::vector<std::pair<std::array<int, 3>, int>> todo;
    for (std::size_t f = 0; f < faces.size(); ++f) todo.push_back({faces[f], int(f)});
    while (!todo.empty()) {
      std::vector<std::pair<std::array<int, 3>, int>> later;
      for (const auto& [f, from] : todo) {
        int e = 0;
        while (e < 3 && !midpoint.count(edgeKey(f[std::size_t(e)], f[std::size_t((e + 1) % 3)]))) ++e;
        if (e == 3) {
          next.push_back(f);
          origin.push_back(from);
          continue;
        }
        const int a = f[std::size_t(e)], b = f[std::size_t((e + 1) % 3)], c = f[std::size_t((e + 2) % 3)];
        const int m = midpoint[edgeKey(a, b)];
        later.push_back({{a, m, c}, from});
        later.push_back({{m, b, c}, from});
      }
      todo.swap(later);
    }
    // The new edges keep the split edge's pairing, not one by angle again (the halves' angles
    // round differently where two faces are nearly coplanar, and the halves must agree for the
    // midpoint to part the sheets): a half of a split edge pairs the halves of the faces its
    // edge paired; an edge inside a split face pairs that face's parts.
    std::unordered_map<std::uint64_t, std::vector<int>> facesOn;  // edges at a midpoint
    for (std::size_t f = 0; f < next.size(); ++f)
      for (int e = 0; e < 3; ++e) {
        const int a = next[f][std::size_t(e)], b = next[f][std::size_t((e + 1) % 3)];
        if (a >= firstMidpoint || b >= firstMidpoint) facesOn[edgeKey(a, b)].push_back(int(f));
      }
    // A pairing of original faces, as pairs of their parts among `list` (the faces on one edge).
    const auto throughOrigin = [&](const FacePairs& pairing, const std::vector<int>& list) {
      FacePairs mapped;
      for (const auto& pr : pairing) {
        int i = -1, j = -1;
        for (const int f : list) {
          if (origin[std::size_t(f)] == pr[0]) i = f;
          if (origin[std::size_t(f)] == pr[1]) j = f;
        }
        if (i >= 0 && j >= 0) mapped.push_back({i, j});
      }
      return mapped;
    };
    std::unordered_map<std::uint64_t, FacePairs> inherited;
    for (auto& [key, list] : facesOn) {
      const int a = int(key >> 32), b = int(key & 0xffffffffu);  // a < b: b is the midpoint
      const std::uint64_t parent = b >= firstMidpoint ? bisect[std::size_t(b - firstMidpoint)] : 0;
      auto& given = inherited[key];
      if (parent != 0 && (int(parent >> 32) == a || int(parent & 0xffffffffu) == a)) {
        given = throughOrigin(*pairsAt(parent), list);
        continue;
      }
      for (std::size_t x = 0; x < list.size(); ++x)
        for (std::size_t y = x + 1; y < list.size(); ++y)
          if (origin[std::size_t(list[x])] == origin[std::size_t(list[y])]) given.push_back({list[x], list[y]});
    }
    // The singular edges not split keep both their pairings too: where a face of theirs was split
    // at another edge, its third vertex is now a midpoint, whose angle around them rounds anew.
    std::unordered_map<std::uint64_t, std::vector<int>> subFaces;
    for (std::size_t f = 0; f < next.size(); ++f)
      for (int e = 0; e < 3; ++e) {
        const std::uint64_t key = edgeKey(next[f][std::size_t(e)], next[f][std::size_t((e + 1) % 3)]);
        if (choices.count(key) && !midpoint.count(key)) subFaces[key].push_back(int(f));
      }
    std::map<std::uint64_t, std::array<FacePairs, 2>> inheritedChoices;
    for (const auto& [key, two] : choices) {
      const auto list = subFaces.find(key);
      if (midpoint.count(key) || list == subFaces.end()) continue;
      inheritedChoices[key] = {throughOrigin(two[0], list->second), throughOrigin(two[1], list->second)};
    }
    faces.swap(next);
    OpenedPinches again = openPinches(faces, positions, false, inherited, inheritedChoices);
    again.edges += int(bisect.size());  // the split edges (their halves are paired as given)
    return again;
  }
  std::vector<std::array<int, 3>> result = faces;
  for (const int v : vertices) {
    const auto roots = umbrellasOf(v);
    std::map<std::size_t, int> copyOf;
    for (const int f : facesAt[v]) copyOf.emplace(roots.at(f), 0);
    if (copyOf.size() < 2) continue;
    ++out.vertices;
    bool first = true;
    for (auto& [root, id] : copyOf) {
      if (first) {
        id = v;
        first = false;
        continue;
      }
      id = int(positions.size());
      positions.push_back(positions[std::size_t(v)]);
    }
    for (const int f : facesAt[v])
      for (int slot = 0; slot < 3; ++slot)
        if (faces[std::size_t(f)][std::size_t(slot)] == v) result[std::size_t(f)][std::size_t(slot)] = copyOf[roots.at(f)];
  }
  faces.swap(result);
  return out;
}

/// Per section-vertex, the component of G'' (`joinable`, Def. 44) holding its section
/// (`sectionOf`: flat ids of `ids`), for markUnjoined. Sections that touch (a point on the
/// contours of both: a trace point where two contours cross; a corner inside sections of three
/// planes) are one object whatever the lattice of G'' saw; a section G'' joins to none gives no
/// evidence either way: its points get -1 (they join anything), as do points of no section.
std::vector<int> pointComponents(const SectionVertices& sv, const std::vector<CuttingPlane>& planes,
                                 const SectionIds& ids, const std::vector<int>& sectionOf,
                                 const std::vector<GraphEdge>& joinable) {
  const std::size_t n = std::size_t(ids.count());
  DisjointSets parts(n);
  std::vector<std::uint8_t> inGraph(n, 0);
  for (const GraphEdge& e : joinable) {
    const std::size_t a = std::size_t(ids.of(e.plane_a, e.section_a)), b = std::size_t(ids.of(e.plane_b, e.section_b));
    parts.unite(a, b);
    inGraph[a] = inGraph[b] = 1;
  }
  for (const SampledRing& r : sv.rings)
    for (const int id : r.points)
      if (sectionOf[std::size_t(id)] >= 0)
        parts.unite(std::size_t(ids.of(r.plane, r.section)), std::size_t(sectionOf[std::size_t(id)]));
  std::vector<SectionLocator> sampled;
  sampled.reserve(sv.sampled.size());
  for (const std::vector<Section>& sections : sv.sampled) sampled.emplace_back(sections);
  for (std::size_t id = 0; id < sv.points.size(); ++id) {
    const SectionVertex& v = sv.points[id];
    if (v.kind != SectionVertex::corner || sectionOf[id] < 0) continue;
    for (int k = 1; k < 3; ++k) {
      const int p = v.planes[std::size_t(k)];
      if (p < 0) continue;
      const int holding = sampled[std::size_t(p)].holding(planeCoordinates(sv, planes, int(id), p));
      if (holding >= 0) parts.unite(std::size_t(sectionOf[id]), std::size_t(ids.of(p, holding)));
    }
  }
  std::vector<int> partOf(sectionOf.size(), -1);
  for (std::size_t id = 0; id < sectionOf.size(); ++id)
    if (sectionOf[id] >= 0 && inGraph[std::size_t(sectionOf[id])]) partOf[id] = int(parts.find(std::size_t(sectionOf[id])));
  return partOf;
}

}  // namespace

DelaunayReconstruction delaunayReconstruction(const std::vector<CuttingPlane>& planes, const SectionArrangement& arr,
                                              const std::vector<BranchingPoint>& branching,
                                              const std::function<void(std::int64_t, std::int64_t)>& progress,
                                              const std::vector<GraphEdge>* joinable) {
  DelaunayReconstruction out;
  SectionVertices sv = sectionVertices(planes, arr, branching);
  const std::size_t cells = std::size_t(sv.cells);
  out.stats.cells_unseen = sv.cells - arr.cells;
  std::vector<CellComplex> cx(cells);
  std::vector<std::uint8_t> pending(cells, 1);
  std::unordered_set<std::uint64_t> contour = contourEdges(sv);
  // D0 with Delaunay conformity: contour edges that are not Delaunay edges are split at their
  // midpoints (in both cells they bound) until all are, or the rounds run out.
  for (int round = 0; round < kConformityRounds; ++round) {
    CellSetup setup = cellSetup(sv);
    addContourEdges(sv, setup);
    std::vector<SectionLocator> sampled;  // step 1's containment tests, per plane
    sampled.reserve(sv.sampled.size());
    for (const std::vector<Section>& s : sv.sampled) sampled.emplace_back(s);
    std::vector<std::vector<std::uint64_t>> missing(cells);
    tbb::parallel_for(std::size_t(0), cells, [&](std::size_t c) {
      if (!pending[c]) return;
      if (onOnePlane(sv, setup.points[c])) {
        cx[c] = CellComplex{};
        cx[c].cell = int(c);
        return;
      }
      cx[c] = cellDelaunay(int(c), setup.points[c], sv, sampled, planes, contour, setup.contour[c], &missing[c]);
    });
    std::unordered_set<std::uint64_t> split;
    for (const auto& m : missing) split.insert(m.begin(), m.end());
    std::fill(pending.begin(), pending.end(), 0);
    if (round + 1 == kConformityRounds) out.stats.contour_edges_not_delaunay = std::int64_t(split.size());
    if (split.empty() || round + 1 == kConformityRounds) break;
    for (std::size_t r = 0; r < sv.rings.size(); ++r) {
      const SampledRing& ring = sv.rings[r];
      for (std::size_t k = ring.points.size(); k-- > 0;) {
        const int a = sv.rings[r].points[k], b = sv.rings[r].points[(k + 1) % sv.rings[r].points.size()];
        if (!split.count(edgeKey(a, b))) continue;
        for (const int c : edgeCells(sv, a, b, ring.plane)) pending[std::size_t(c)] = 1;
        splitRingEdge(sv, planes, r, k);
      }
    }
    resampleSections(sv, planes);
    contour = contourEdges(sv);
  }
  for (const SectionVertex& v : sv.points) out.stats.conformity_points += v.kind == SectionVertex::conformity;
  // Each section-vertex's section as a flat id (-1: none), so that a cell's pairs sort as integers
  // (in the flat ids' order, which is GraphEdge's (plane, section) order).
  const SectionIds ids(planes);
  std::vector<int> sectionOf(sv.points.size(), -1);
  for (std::size_t id = 0; id < sv.points.size(); ++id)
    if (sv.points[id].section >= 0) sectionOf[id] = ids.of(sv.points[id].planes[0], sv.points[id].section);
  // Step 1's addition (not the thesis'): tetrahedra joining components of G'' (Def. 44).
  if (joinable) {
    const std::vector<int> partOf = pointComponents(sv, planes, ids, sectionOf, *joinable);
    tbb::parallel_for(std::size_t(0), cells, [&](std::size_t c) { markUnjoined(cx[c], partOf); });
  }
  // Steps 2 and 3 in every cell.
  tbb::parallel_for(std::size_t(0), cells, [&](std::size_t c) { pruneCell(cx[c]); });
  if (progress) progress(std::int64_t(cells), std::int64_t(cells));

  // Points on each plane (the vertices of its triangulation when gluing).
  std::vector<std::vector<int>> onPlane(planes.size());
  for (std::size_t id = 0; id < sv.points.size(); ++id)
    for (const int p : sv.points[id].planes)
      if (p >= 0 && !sv.points[id].cells.empty()) onPlane[std::size_t(p)].push_back(int(id));

  // The boundary: every cell's non-grounded boundary faces, and each plane's flat faces.
  std::vector<CellBoundary> bounds(cells);
  tbb::parallel_for(std::size_t(0), cells, [&](std::size_t c) { bounds[c] = cellBoundary(cx[c], sv); });
  std::vector<PlaneFootprint> fp(planes.size());
  std::vector<std::array<int, 3>> faces;
  for (const CellBoundary& b : bounds) {
    faces.insert(faces.end(), b.faces.begin(), b.faces.end());
    for (const auto& [p, side, t] : b.ground) fp[std::size_t(p)].covered[std::size_t(side)].push_back(t);
    for (const auto& [p, e] : b.rims) fp[std::size_t(p)].rims.push_back(e);
  }
  bounds.clear();
  std::vector<PlaneBoundary> flat(planes.size());
  const int firstNew = int(sv.points.size());
  tbb::parallel_for(std::size_t(0), planes.size(), [&](std::size_t p) {
    flat[p] = planeBoundary(int(p), onPlane[p], fp[p], sv, planes, firstNew);
  });
  std::vector<Vec3> positions;
  positions.reserve(sv.points.size());
  for (const SectionVertex& v : sv.points) positions.push_back(v.x);
  std::vector<int> newPointPlane;  // the plane whose gluing made each point beyond sv.points
  for (std::size_t p = 0; p < flat.size(); ++p) newPointPlane.insert(newPointPlane.end(), flat[p].new_points.size(), int(p));
  for (const PlaneBoundary& f : flat) {
    const int offset = int(positions.size()) - firstNew;
    for (std::array<int, 3> t : f.faces) {
      for (int& v : t)
        if (v >= firstNew) v += offset;
      faces.push_back(t);
      ++out.stats.flat_faces;
    }
    positions.insert(positions.end(), f.new_points.begin(), f.new_points.end());
  }
  out.stats.constraint_crossings = std::int64_t(positions.size() - sv.points.size());
  // The planes a boundary point lies on: a section-vertex's, or for a point made where a plane's
  // constraints crossed, that plane only.
  const auto planesOfPoint = [&](int id) {
    return std::size_t(id) < sv.points.size() ? sv.points[std::size_t(id)].planes
                                              : std::array<int, 3>{newPointPlane[std::size_t(id) - sv.points.size()], -1, -1};
  };
  const auto pointOnPlane = [&](int id, int p) {
    const std::array<int, 3> q = planesOfPoint(id);
    return p >= 0 && (q[0] == p || q[1] == p || q[2] == p);
  };
  out.stats.welded_vertices = weldNearVertices(faces, positions, 1e-2 * arr.sample_spacing_mm, [&](int id) {
    const std::array<int, 3> q = planesOfPoint(id);
    return int(q[0] >= 0) + int(q[1] >= 0) + int(q[2] >= 0);
  }, [&](int rep, int id) {
    for (const int p : planesOfPoint(id))
      if (p >= 0 && !pointOnPlane(rep, p)) return false;
    return true;
  });
  splitTJunctions(faces, [&](int id) { return positions[std::size_t(id)]; });
  out.stats.holes_closed = closeFlatHoles(faces, positions, [&](const std::vector<int>& hole) {
    for (const int p : planesOfPoint(hole[0]))
      if (std::all_of(hole.begin(), hole.end(), [&](int id) { return pointOnPlane(id, p); })) return true;
    return false;
  });
  const OpenedPinches opened = openPinches(faces, positions);
  // A thousandth of the sample spacing: sliver shells measured 3e-8 mm thick against 0.3 mm
  // spacing (800 random planes through the genus-2 solid: six); the thinnest true void seen, a
  // one-pixel hole of a section repeated on neighbouring frames, 7e-3 mm against 0.1 mm.
  out.stats.flat_shells_dropped = dropFlatShells(faces, positions, 1e-3 * arr.sample_spacing_mm);
  out.stats.singular_edges = opened.edges;
  out.stats.singular_vertices = opened.vertices;
  for (const auto& [key, n] : edgeUses(faces)) out.stats.open_edges += n != 2;  // the mesh is then not closed

  // The mesh: used points in id order.
  std::vector<int> used;
  for (const auto& f : faces) used.insert(used.end(), f.begin(), f.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::vector<std::uint32_t> index(positions.size(), 0);
  for (const int id : used) {
    index[std::size_t(id)] = std::uint32_t(out.mesh.vertices.size());
    out.mesh.vertices.push_back(positions[std::size_t(id)].cast<float>());
  }
  std::sort(faces.begin(), faces.end());
  for (const auto& f : faces)
    out.mesh.triangles.push_back({index[std::size_t(f[0])], index[std::size_t(f[1])], index[std::size_t(f[2])]});

  // Statistics, tetrahedra and the connections the solid realises.
  // Per cell in parallel (a cell's pairs are its own: the edge names the cell), then in cell order.
  struct CellTally {
    DelaunayStats stats;
    std::size_t kept = 0;
    std::vector<GraphEdge> joined;
  };
  std::vector<CellTally> tally(cells);
  tbb::parallel_for(std::size_t(0), cells, [&](std::size_t c) {
    CellTally& T = tally[c];
    const CellComplex& C = cx[c];
    std::vector<std::uint64_t> pairs;
    for (std::size_t t = 0; t < C.v.size(); ++t) {
      switch (C.type[t]) {
        case TetType::vf: ++T.stats.d0.vf; break;
        case TetType::ee: ++T.stats.d0.ee; break;
        case TetType::evv: ++T.stats.d0.evv; break;
        case TetType::vvvv: ++T.stats.d0.vvvv; break;
        case TetType::flat: ++T.stats.d0.flat; break;
      }
      T.stats.external += C.external[t] && C.type[t] != TetType::flat;
      T.stats.unjoined += C.unjoined[t];
      if (!C.kept[t]) continue;
      ++T.kept;
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) {
          const std::size_t a = std::size_t(C.v[t][std::size_t(i)]), b = std::size_t(C.v[t][std::size_t(j)]);
          if (sectionOf[a] < 0 || sectionOf[b] < 0 || sv.points[a].planes[0] == sv.points[b].planes[0]) continue;
          const auto [lo, hi] = std::minmax(sectionOf[a], sectionOf[b]);
          pairs.push_back(std::uint64_t(lo) << 32 | std::uint64_t(hi));
        }
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    for (const std::uint64_t k : pairs) {
      const std::size_t lo = std::size_t(k >> 32), hi = std::size_t(k & 0xffffffffu);
      const int pl = ids.planeOf(int(lo)), ph = ids.planeOf(int(hi));
      T.joined.push_back({pl, int(lo) - ids.first(pl), ph, int(hi) - ids.first(ph), int(c)});
    }
  });
  std::vector<std::size_t> firstTet(cells + 1, 0);
  std::vector<GraphEdge> joined;
  for (std::size_t c = 0; c < cells; ++c) {
    const CellComplex& C = cx[c];
    const DelaunayStats& S = tally[c].stats;
    if (!C.v.empty()) ++out.stats.cells;
    out.stats.d1 += C.d1;
    out.stats.d2 += C.d2;
    out.stats.d3 += C.d3;
    out.stats.d0.vf += S.d0.vf;
    out.stats.d0.ee += S.d0.ee;
    out.stats.d0.evv += S.d0.evv;
    out.stats.d0.vvvv += S.d0.vvvv;
    out.stats.d0.flat += S.d0.flat;
    out.stats.external += S.external;
    out.stats.unjoined += S.unjoined;
    firstTet[c + 1] = firstTet[c] + tally[c].kept;
    joined.insert(joined.end(), tally[c].joined.begin(), tally[c].joined.end());
  }
  // D3's tetrahedra on the section-vertices they use, numbered in id order.
  std::vector<int> vertexOf(sv.points.size(), -1);
  for (std::size_t c = 0; c < cells; ++c) {
    const CellComplex& C = cx[c];
    for (std::size_t t = 0; t < C.v.size(); ++t)
      if (C.kept[t])
        for (const int id : C.v[t]) vertexOf[std::size_t(id)] = 0;
  }
  for (std::size_t id = 0; id < sv.points.size(); ++id)
    if (vertexOf[id] == 0) {
      vertexOf[id] = int(out.tetrahedra.vertices.size());
      out.tetrahedra.vertices.push_back(sv.points[id].x);
    }
  out.tetrahedra.corners.resize(firstTet[cells]);
  tbb::parallel_for(std::size_t(0), cells, [&](std::size_t c) {
    const CellComplex& C = cx[c];
    std::size_t k = firstTet[c];
    for (std::size_t t = 0; t < C.v.size(); ++t) {
      if (!C.kept[t]) continue;
      for (int i = 0; i < 4; ++i)
        out.tetrahedra.corners[k][std::size_t(i)] = vertexOf[std::size_t(C.v[t][std::size_t(i)])];
      ++k;
    }
  });
  std::sort(joined.begin(), joined.end());
  out.connections = std::move(joined);
  for (const SectionVertex& v : sv.points) out.stats.branching_points += v.kind == SectionVertex::branching && !v.cells.empty();
  for (const auto& pts : cellSetup(sv).points) out.stats.section_vertices += std::int64_t(pts.size());
  return out;
}

}  // namespace xsect
