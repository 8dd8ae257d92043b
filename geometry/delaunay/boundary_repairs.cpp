// Repairs of method 3's glued boundary (see boundary_repairs.h).
#include "geometry/delaunay/boundary_repairs.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <unordered_set>

#include "geometry/core/disjoint_sets.h"
#include "geometry/core/near_points.h"
#include "geometry/delaunay/section_vertices.h"

namespace xsect {

std::unordered_map<std::uint64_t, int> edgeUses(const std::vector<std::array<int, 3>>& faces) {
  std::unordered_map<std::uint64_t, int> uses;
  for (const auto& f : faces)
    for (int e = 0; e < 3; ++e) ++uses[edgeKey(f[std::size_t(e)], f[std::size_t((e + 1) % 3)])];
  return uses;
}

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

int weldNearVertices(std::vector<std::array<int, 3>>& faces, const std::vector<Vec3>& positions, double tolerance,
                     const std::function<int(int)>& planesOf, const std::function<bool(int, int)>& covers) {
  std::vector<int> used;
  for (const auto& f : faces) used.insert(used.end(), f.begin(), f.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  NearPoints near(tolerance, positions.size());
  for (const int id : used) near.add(id, positions[std::size_t(id)]);
  std::unordered_map<int, int> to;
  DisjointSets sets(used.size());
  std::unordered_map<int, std::size_t> slot;
  for (std::size_t k = 0; k < used.size(); ++k) slot[used[k]] = k;
  for (const int id : used) {
    const Vec3& x = positions[std::size_t(id)];
    near.forEachCandidate(x, [&](int other) {
      if (other != id && (positions[std::size_t(other)] - x).norm() < tolerance) sets.unite(slot[id], slot[other]);
    });
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

int dropFlatShells(std::vector<std::array<int, 3>>& faces, const std::vector<Vec3>& positions, double thickness,
                   double openArea) {
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
  std::unordered_set<std::size_t> open;
  for (const auto& [key, n] : edgeUses(faces))
    if (n % 2 != 0) open.insert(sets.find(std::size_t(key >> 32)));
  std::unordered_set<std::size_t> flat;
  for (const auto& [root, s] : shell)
    if (std::abs(s[0]) < thickness * s[1] && (!open.count(root) || 0.5 * s[1] < openArea))
      flat.insert(root);  // 3|V|/A = |6V| / (2A)
  if (flat.empty()) return 0;
  faces.erase(std::remove_if(faces.begin(), faces.end(),
                             [&](const std::array<int, 3>& f) { return flat.count(sets.find(std::size_t(f[0]))) > 0; }),
              faces.end());
  return int(flat.size());
}

/// Face pairs across each edge (the faces of one sheet there): `pairs` for an edge in two faces or
/// given; at an edge in 2k > 2 faces, sorted by angle around it, two pairings alternate: across
/// the empty wedges (`join`, preferred) and across the solid wedges (`apart`): `choices`.
struct EdgePairing {
  std::unordered_map<std::uint64_t, FacePairs> pairs;
  std::map<std::uint64_t, std::array<FacePairs, 2>> choices;  ///< singular edges: {join, apart}
  int singular = 0;                                           ///< edges in 4, 6, ... faces
};

EdgePairing pairFacesAcrossEdges(const std::vector<std::array<int, 3>>& faces, const std::vector<Vec3>& positions,
                                 const std::unordered_map<std::uint64_t, FacePairs>& given,
                                 const std::map<std::uint64_t, std::array<FacePairs, 2>>& givenChoices) {
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
  EdgePairing e;
  std::unordered_map<std::uint64_t, FacePairs>& pairs = e.pairs;
  std::map<std::uint64_t, std::array<FacePairs, 2>>& choices = e.choices;  // singular edges
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
    ++e.singular;
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
  return e;
}

/// The faces at each vertex, ascending (a face twice at a vertex it repeats), as offsets into one
/// array: a map of lists per vertex, and two per vertex below, made this the slowest repair
/// (random-400 with method 3: 1.7 s of one core).
struct VertexFaces {
  std::vector<int> first, all;
  std::pair<std::vector<int>::const_iterator, std::vector<int>::const_iterator> at(int v) const {
    return {all.begin() + first[std::size_t(v)], all.begin() + first[std::size_t(v) + 1]};
  }
};

VertexFaces vertexFaces(const std::vector<std::array<int, 3>>& faces, std::size_t vertices) {
  VertexFaces vf;
  vf.first.assign(vertices + 1, 0);
  vf.all.resize(3 * faces.size());
  for (const auto& f : faces)
    for (const int v : f) ++vf.first[std::size_t(v) + 1];
  for (std::size_t v = 0; v < vertices; ++v) vf.first[v + 1] += vf.first[v];
  std::vector<int> fill(vf.first.begin(), vf.first.end() - 1);
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (const int v : faces[f]) vf.all[std::size_t(fill[std::size_t(v)]++)] = int(f);
  return vf;
}

/// Umbrellas: the faces around each vertex joined through the pairs of the edges at the vertex
/// (a singular edge's as chosen: join, or apart).
class Umbrellas {
 public:
  Umbrellas(const std::vector<std::array<int, 3>>& faces, const VertexFaces& at, const EdgePairing& pairing)
      : faces_(faces), at_(at), pairing_(pairing) {
    for (const auto& [key, two] : pairing.choices) chosen_[key] = 0;
  }
  void choose(std::uint64_t key, int which) { chosen_[key] = which; }

  /// The face pairs across edge `key` (null: none).
  const FacePairs* pairsAt(std::uint64_t key) const {
    const auto c = chosen_.find(key);
    if (c != chosen_.end()) return &pairing_.choices.find(key)->second[std::size_t(c->second)];
    const auto it = pairing_.pairs.find(key);
    return it == pairing_.pairs.end() ? nullptr : &it->second;
  }

  /// Per face at v (in at(v)'s order), the smallest index of its umbrella; a face listed twice
  /// counts where it is listed last.
  std::vector<std::size_t> of(int v) const {
    const auto range = at_.at(v);  // plain locals: C++17 lambdas cannot capture structured bindings
    const auto begin = range.first, end = range.second;
    const std::size_t n = std::size_t(end - begin);
    const auto at = [&](int f) -> std::ptrdiff_t {
      const auto it = std::upper_bound(begin, end, f);
      return it != begin && *(it - 1) == f ? (it - 1) - begin : -1;
    };
    DisjointSets umbrella(n);
    for (auto f = begin; f != end; ++f)
      for (const int x : faces_[std::size_t(*f)]) {
        if (x == v) continue;
        const auto* ps = pairsAt(edgeKey(v, x));
        if (!ps) continue;
        for (const auto& pr : *ps) {
          const std::ptrdiff_t i = at(pr[0]), j = at(pr[1]);
          if (i >= 0 && j >= 0) umbrella.unite(std::size_t(i), std::size_t(j));
        }
      }
    std::vector<std::size_t> roots(n);
    for (std::size_t k = 0; k < n; ++k) roots[k] = umbrella.find(std::size_t(at(begin[std::ptrdiff_t(k)])));
    return roots;
  }

 private:
  const std::vector<std::array<int, 3>>& faces_;
  const VertexFaces& at_;
  const EdgePairing& pairing_;
  std::map<std::uint64_t, int> chosen_;  ///< singular edge -> 0 (join) or 1 (apart)
};

/// Splits each edge of `bisect` at its midpoint and runs openPinches again on the split faces,
/// the new edges keeping the split edges' pairings (see below).
OpenedPinches bisectAndOpen(std::vector<std::array<int, 3>>& faces, std::vector<Vec3>& positions,
                            const std::vector<std::uint64_t>& bisect, const EdgePairing& pairing,
                            const Umbrellas& umbrellas) {
  const std::map<std::uint64_t, std::array<FacePairs, 2>>& choices = pairing.choices;
  const auto pairsAt = [&](std::uint64_t key) { return umbrellas.pairsAt(key); };
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

/// Every pinched vertex (its faces in two umbrellas or more) given one copy per umbrella: which
/// are pinched in parallel, then each opened in order (the copies are numbered in vertex order).
/// Returns the vertices opened.
int openPinchedVertices(std::vector<std::array<int, 3>>& faces, std::vector<Vec3>& positions, const VertexFaces& at,
                        const Umbrellas& umbrellas) {
  std::vector<int> vertices;
  for (std::size_t v = 0; v < positions.size(); ++v)
    if (at.first[v + 1] > at.first[v]) vertices.push_back(int(v));
  int opened = 0;
  std::vector<std::array<int, 3>> result = faces;
  std::vector<std::uint8_t> pinched(vertices.size(), 0);
  tbb::parallel_for(std::size_t(0), vertices.size(), [&](std::size_t k) {
    const std::vector<std::size_t> roots = umbrellas.of(vertices[k]);
    pinched[k] = std::any_of(roots.begin(), roots.end(), [&](std::size_t r) { return r != roots.front(); });
  });
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    if (!pinched[k]) continue;
    const int v = vertices[k];
    const auto roots = umbrellas.of(v);
    const auto [begin, end] = at.at(v);
    std::map<std::size_t, int> copyOf;
    for (const std::size_t r : roots) copyOf.emplace(r, 0);
    if (copyOf.size() < 2) continue;
    ++opened;
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
    for (auto f = begin; f != end; ++f)
      for (int slot = 0; slot < 3; ++slot)
        if (faces[std::size_t(*f)][std::size_t(slot)] == v)
          result[std::size_t(*f)][std::size_t(slot)] = copyOf[roots[std::size_t(std::upper_bound(begin, end, *f) - 1 - begin)]];
  }
  faces.swap(result);
  return opened;
}

OpenedPinches openPinches(std::vector<std::array<int, 3>>& faces, std::vector<Vec3>& positions, bool splitting,
                          const std::unordered_map<std::uint64_t, FacePairs>& given,
                          const std::map<std::uint64_t, std::array<FacePairs, 2>>& givenChoices) {
  OpenedPinches out;
  const EdgePairing pairing = pairFacesAcrossEdges(faces, positions, given, givenChoices);
  out.edges = pairing.singular;
  const VertexFaces at = vertexFaces(faces, positions.size());
  Umbrellas umbrellas(faces, at, pairing);
  // A singular edge stays singular when, at both its ends, all its faces fall in one umbrella:
  // such an edge is split at its midpoint (see above), or, on the second pass, paired the other
  // way (which then splits an end's umbrella).
  std::vector<std::uint64_t> bisect;
  for (const auto& [key, two] : pairing.choices) {
    const int a = int(key >> 32), b = int(key & 0xffffffffu);
    const auto split = [&](int v) {
      const auto roots = umbrellas.of(v);
      const auto [begin, end] = at.at(v);
      std::set<std::size_t> seen;
      for (const auto& pr : *umbrellas.pairsAt(key)) seen.insert(roots.at(std::size_t(std::upper_bound(begin, end, pr[0]) - 1 - begin)));
      return seen.size() > 1;
    };
    if (split(a) || split(b)) continue;
    if (splitting) bisect.push_back(key);
    else umbrellas.choose(key, 1);
  }
  if (!bisect.empty()) return bisectAndOpen(faces, positions, bisect, pairing, umbrellas);
  out.vertices = openPinchedVertices(faces, positions, at, umbrellas);
  return out;
}

}  // namespace xsect
