// D0 of one cell and its pruning to D3 (see cell_complex.h; thesis ch. 3 §1-2).
#include "geometry/delaunay/cell_complex.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <deque>
#include <numeric>
#include <unordered_map>

#include "geometry/core/disjoint_sets.h"
#include "geometry/core/polygon.h"
#include "geometry/core/section_locator.h"

namespace xsect {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_3<int, K>;
using Cb = CGAL::Triangulation_cell_base_with_info_3<int, K, CGAL::Delaunay_triangulation_cell_base_3<K>>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb>;
using DT = CGAL::Delaunay_triangulation_3<K, Tds>;

/// Whether point q (plane coordinates of `plane`) lies in the plane's sampled sections.
bool inSampledSections(const std::vector<SectionLocator>& sampled, int plane, const Vec2& q) {
  return sampled[std::size_t(plane)].holding(q) >= 0;
}

}  // namespace

std::unordered_set<std::uint64_t> contourEdges(const SectionVertices& sv) {
  std::unordered_set<std::uint64_t> out;
  for (const SampledRing& r : sv.rings)
    for (std::size_t k = 0; k < r.points.size(); ++k) out.insert(edgeKey(r.points[k], r.points[(k + 1) % r.points.size()]));
  return out;
}

int commonPlane(const SectionVertices& sv, const int* ids, int n) {
  const SectionVertex& first = sv.points[std::size_t(ids[0])];
  for (const int p : first.planes) {
    if (p < 0) continue;
    bool all = true;
    for (int k = 1; k < n && all; ++k) all = sv.points[std::size_t(ids[k])].on(p);
    if (all) return p;
  }
  return -1;
}

namespace {

/// The finite tetrahedra of dt in a canonical order (by sorted vertex ids): their vertices and
/// neighbours (-1: the infinite cell) into c, each cell's info its index.
void canonicalTetrahedra(DT& dt, CellComplex& c) {
  std::vector<DT::Cell_handle> cells;
  for (auto it = dt.finite_cells_begin(); it != dt.finite_cells_end(); ++it) cells.push_back(it);
  std::vector<std::array<int, 4>> sortedIds(cells.size());
  for (std::size_t t = 0; t < cells.size(); ++t) {
    for (int i = 0; i < 4; ++i) sortedIds[t][std::size_t(i)] = cells[t]->vertex(i)->info();
    std::sort(sortedIds[t].begin(), sortedIds[t].end());
  }
  std::vector<std::size_t> order(cells.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return sortedIds[a] < sortedIds[b]; });
  for (std::size_t t = 0; t < order.size(); ++t) cells[order[t]]->info() = int(t);
  const std::size_t n = cells.size();
  c.v.resize(n);
  c.nb.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    const DT::Cell_handle h = cells[order[t]];
    for (int i = 0; i < 4; ++i) {
      c.v[t][std::size_t(i)] = h->vertex(i)->info();
      const DT::Cell_handle o = h->neighbor(i);
      c.nb[t][std::size_t(i)] = dt.is_infinite(o) ? -1 : o->info();
    }
  }
}

/// The contour edges of the cell that are not edges of dt, into `missing`.
void missingContourEdges(const DT& dt, const std::vector<std::uint64_t>& cellContourEdges,
                         std::vector<std::uint64_t>* missing) {
  missing->clear();
  std::unordered_map<int, DT::Vertex_handle> vertexOf;
  for (auto it = dt.finite_vertices_begin(); it != dt.finite_vertices_end(); ++it) vertexOf[it->info()] = it;
  for (const std::uint64_t e : cellContourEdges) {
    const auto a = vertexOf.find(int(e >> 32)), b = vertexOf.find(int(e & 0xffffffffu));
    DT::Cell_handle ch;
    int i = 0, j = 0;
    if (a == vertexOf.end() || b == vertexOf.end() || !dt.is_edge(a->second, b->second, ch, i, j)) missing->push_back(e);
  }
}

/// Types and step 1: each tetrahedron's grounded faces and edges, whether it is external (a
/// grounded face or edge outside the sampled sections), and its type (flat, vf, ee, evv, vvvv).
void classifyTetrahedra(const SectionVertices& sv, const std::vector<SectionLocator>& sampled,
                        const std::vector<CuttingPlane>& planes, const std::unordered_set<std::uint64_t>& contour,
                        CellComplex& c) {
  const std::size_t n = c.v.size();
  c.type.resize(n);
  c.external.assign(n, 0);
  c.kept.assign(n, 0);
  c.grounded_faces.assign(n, 0);
  c.grounded_edges.assign(n, 0);
  c.unjoined.assign(n, 0);
  // Step 1's test of a grounded edge (not a contour edge: its midpoint in the sampled sections),
  // once per edge and plane: an edge lies in several tetrahedra of the cell (multiaxial-3x40:
  // 1.17 million edges for 3.09 million tests). Open addressing on (edge, plane).
  struct EdgeTest {
    std::uint64_t key = 0;
    int plane = -1;
    bool outside = false;
  };
  std::size_t slots = 16;
  while (slots <= 18 * n) slots *= 2;  // more than 6 edges x 3 planes per tetrahedron: never full
  std::vector<EdgeTest> tested(slots);
  const auto edgeOutside = [&](int a, int b, int p) {
    const std::uint64_t key = edgeKey(a, b);
    std::size_t h = std::size_t((key * 0x9e3779b97f4a7c15ULL + std::uint64_t(p)) >> 20) & (slots - 1);
    for (;; h = (h + 1) & (slots - 1)) {
      EdgeTest& e = tested[h];
      if (e.plane < 0) {
        e.key = key;
        e.plane = p;
        const Vec2 q = 0.5 * (planeCoordinates(sv, planes, a, p) + planeCoordinates(sv, planes, b, p));
        e.outside = !contour.count(key) && !inSampledSections(sampled, p, q);
        return e.outside;
      }
      if (e.key == key && e.plane == p) return e.outside;
    }
  };
  for (std::size_t t = 0; t < n; ++t) {
    const auto& V = c.v[t];
    if (commonPlane(sv, V.data(), 4) >= 0) {
      c.type[t] = TetType::flat;
      continue;
    }
    bool groundedFace = false, external = false;
    for (int i = 0; i < 4; ++i) {
      int f[3], m = 0;
      for (int k = 0; k < 4; ++k)
        if (k != i) f[m++] = V[std::size_t(k)];
      const int p = commonPlane(sv, f, 3);
      if (p < 0) continue;
      const Vec2 q0 = planeCoordinates(sv, planes, f[0], p), q1 = planeCoordinates(sv, planes, f[1], p),
                 q2 = planeCoordinates(sv, planes, f[2], p);
      // Three contour samples of a straight stretch are collinear up to rounding: their "triangle"
      // is a piece of the contour, neither internal nor external (ch. 3 §1), and its intersection
      // with the section, the ground (Def. 50), has no area. Counted as a ground, it kept a
      // zero-volume tetrahedron standing on it alone: a fin of the mesh (the plane gluing's sliver
      // test).
      if (isSliverTriangle(q0, q1, q2)) continue;
      groundedFace = true;
      c.grounded_faces[t] = std::uint8_t(c.grounded_faces[t] | (1 << i));
      if (!inSampledSections(sampled, p, (q0 + q1 + q2) / 3.0)) external = true;
    }
    bool grounded[6];
    for (int e = 0; e < 6; ++e) {
      const int ab[2] = {V[std::size_t(kEdges[e][0])], V[std::size_t(kEdges[e][1])]};
      grounded[e] = false;
      for (const int p : sv.points[std::size_t(ab[0])].planes) {
        if (p < 0 || !sv.points[std::size_t(ab[1])].on(p)) continue;
        grounded[e] = true;
        if (edgeOutside(ab[0], ab[1], p)) external = true;
      }
    }
    c.external[t] = external;
    for (int e = 0; e < 6; ++e)
      if (grounded[e]) c.grounded_edges[t] = std::uint8_t(c.grounded_edges[t] | (1 << e));
    if (groundedFace) c.type[t] = TetType::vf;
    else if ((grounded[0] && grounded[5]) || (grounded[1] && grounded[4]) || (grounded[2] && grounded[3]))
      c.type[t] = TetType::ee;
    else if (std::any_of(grounded, grounded + 6, [](bool g) { return g; }))
      c.type[t] = TetType::evv;
    else
      c.type[t] = TetType::vvvv;
  }
}

}  // namespace

CellComplex cellDelaunay(int cell, const std::vector<int>& ids, const SectionVertices& sv,
                         const std::vector<SectionLocator>& sampled, const std::vector<CuttingPlane>& planes,
                         const std::unordered_set<std::uint64_t>& contour,
                         const std::vector<std::uint64_t>& cellContourEdges, std::vector<std::uint64_t>* missing) {
  CellComplex c;
  c.cell = cell;
  std::vector<std::pair<K::Point_3, int>> pts;
  pts.reserve(ids.size());
  for (const int id : ids) {
    const Vec3& x = sv.points[std::size_t(id)].x;
    pts.push_back({K::Point_3(x.x(), x.y(), x.z()), id});
  }
  DT dt(pts.begin(), pts.end());
  if (dt.dimension() < 3) return c;
  canonicalTetrahedra(dt, c);
  if (missing) missingContourEdges(dt, cellContourEdges, missing);
  classifyTetrahedra(sv, sampled, planes, contour, c);
  return c;
}

namespace {

int indexIn(const std::array<int, 4>& v, int p) {
  for (int i = 0; i < 4; ++i)
    if (v[std::size_t(i)] == p) return i;
  return -1;
}

/// The shell of edge (a, b) from tetrahedron t0 (which contains it): the tetrahedra around the
/// edge in rotational order, into `shell`; `closed` when they go all the way round. Reuses the
/// room of `shell` and `scratch` (the pruning walks millions of shells).
void shellOf(const CellComplex& c, int t0, int a, int b, std::vector<int>& shell, std::vector<int>& scratch,
             bool* closed) {
  const auto walk = [&](int exitOpposite, std::vector<int>& seq) {
    int cur = t0, opp = exitOpposite;
    for (std::size_t guard = 0; guard < c.v.size() + 1; ++guard) {
      const int nxt = c.nb[std::size_t(cur)][std::size_t(indexIn(c.v[std::size_t(cur)], opp))];
      if (nxt < 0) return false;
      if (nxt == t0) return true;
      seq.push_back(nxt);
      const auto& V = c.v[std::size_t(nxt)];
      int w = -1;
      for (int k = 0; k < 4; ++k)
        if (c.nb[std::size_t(nxt)][std::size_t(k)] == cur) w = V[std::size_t(k)];
      int d = -1;
      for (int k = 0; k < 4; ++k) {
        const int x = V[std::size_t(k)];
        if (x != a && x != b && x != w) d = x;
      }
      cur = nxt;
      opp = d;
    }
    return false;
  };
  const auto& V0 = c.v[std::size_t(t0)];
  int others[2], m = 0;
  for (int k = 0; k < 4; ++k)
    if (V0[std::size_t(k)] != a && V0[std::size_t(k)] != b) others[m++] = V0[std::size_t(k)];
  std::vector<int>& fwd = scratch;
  fwd.clear();
  shell.clear();
  *closed = walk(others[0], fwd);
  if (!*closed) {
    walk(others[1], shell);  // backwards from t0, reversed below
    std::reverse(shell.begin(), shell.end());
  }
  shell.push_back(t0);
  shell.insert(shell.end(), fwd.begin(), fwd.end());
}

/// Calls f(run) for each run of consecutive tetrahedra for which `in` holds, around a shell
/// (cyclic when closed: runs then start after a tetrahedron not in), in order; `run` is the room
/// each run is gathered in. f may change `in` for the run's own tetrahedra.
template <class F>
void forEachRun(const std::vector<int>& shell, bool closed, const std::vector<std::uint8_t>& in, std::vector<int>& run,
                F&& f) {
  const std::size_t n = shell.size();
  std::size_t start = 0;
  if (closed) {
    while (start < n && in[std::size_t(shell[start])]) ++start;
    if (start == n) {  // the whole way round
      run.assign(shell.begin(), shell.end());
      f(run);
      return;
    }
  }
  run.clear();
  for (std::size_t k = 0; k < n; ++k) {
    const int t = shell[(start + k) % n];
    if (in[std::size_t(t)]) {
      run.push_back(t);
    } else if (!run.empty()) {
      f(run);
      run.clear();
    }
  }
  if (!run.empty()) f(run);
}

}  // namespace

void markUnjoined(CellComplex& c, const std::vector<int>& partOf) {
  for (std::size_t t = 0; t < c.v.size(); ++t) {
    if (c.type[t] == TetType::flat || c.external[t]) continue;
    for (int e = 0; e < 6 && !c.unjoined[t]; ++e) {
      const int a = partOf[std::size_t(c.v[t][std::size_t(kEdges[e][0])])];
      const int b = partOf[std::size_t(c.v[t][std::size_t(kEdges[e][1])])];
      if (a >= 0 && b >= 0 && a != b) c.unjoined[t] = 1;
    }
  }
}

namespace {

/// Room for shells and their runs, reused.
struct ShellRoom {
  std::vector<int> shell, scratch, run;
};

/// The work list of grounded edges: an edge is re-examined when a tetrahedron of its shell is
/// removed. The grounded edges are numbered once, (key, 6 t + e) sorted (only grounded edges have
/// shells Def. 50 constrains), so that the list's membership is a flag per edge, not a hash set:
/// on multiaxial-3x40 the hashing was a third of the pruning's time.
class EdgeWork {
 public:
  explicit EdgeWork(const CellComplex& c) : edgeOf_(6 * c.v.size(), -1) {
    const std::size_t n = c.v.size();
    std::vector<std::pair<std::uint64_t, int>> slots;
    for (std::size_t t = 0; t < n; ++t)
      for (int e = 0; e < 6; ++e)
        if (c.grounded_edges[t] >> e & 1)
          slots.push_back({edgeKey(c.v[t][std::size_t(kEdges[e][0])], c.v[t][std::size_t(kEdges[e][1])]), int(6 * t) + e});
    std::sort(slots.begin(), slots.end());
    for (std::size_t q = 0; q < slots.size(); ++q) {
      if (q == 0 || slots[q].first != slots[q - 1].first) keys_.push_back(slots[q].first);
      edgeOf_[std::size_t(slots[q].second)] = int(keys_.size()) - 1;
    }
    queued_.assign(keys_.size(), 0);
  }
  /// Queues tetrahedron t's grounded edges not queued yet.
  void push(std::size_t t) {
    for (int e = 0; e < 6; ++e) {
      const int edge = edgeOf_[6 * t + std::size_t(e)];
      if (edge < 0 || queued_[std::size_t(edge)]) continue;
      queued_[std::size_t(edge)] = 1;
      work_.push_back({edge, int(t)});
    }
  }
  bool empty() const { return work_.empty(); }
  /// The next (edge, a tetrahedron of its shell).
  std::pair<int, int> pop() {
    const std::pair<int, int> w = work_.front();
    work_.pop_front();
    queued_[std::size_t(w.first)] = 0;
    return w;
  }
  std::uint64_t key(int edge) const { return keys_[std::size_t(edge)]; }

 private:
  std::vector<int> edgeOf_;
  std::vector<std::uint64_t> keys_;
  std::deque<std::pair<int, int>> work_;
  std::vector<std::uint8_t> queued_;
};

/// Def. 50 at the queued edges: a run of kept tetrahedra around an edge that reaches no
/// tetrahedron with a grounded triangle through it is removed (its edges queued again).
void pruneAtEdges(CellComplex& c, EdgeWork& work, ShellRoom& room) {
  while (!work.empty()) {
    const auto [edge, t0] = work.pop();
    const std::uint64_t key = work.key(edge);
    const int a = int(key >> 32), b = int(key & 0xffffffffu);
    bool closed = false;
    shellOf(c, t0, a, b, room.shell, room.scratch, &closed);
    forEachRun(room.shell, closed, c.kept, room.run, [&](const std::vector<int>& r) {
      bool grounded = false;
      // Def. 50: reaching a tetrahedron with a grounded triangle through e.
      for (const int t : r)
        for (int i = 0; i < 4; ++i) {
          const int x = c.v[std::size_t(t)][std::size_t(i)];
          if (x != a && x != b && (c.grounded_faces[std::size_t(t)] >> i & 1)) grounded = true;
        }
      if (grounded) return;
      for (const int t : r) {
        c.kept[std::size_t(t)] = 0;
        work.push(std::size_t(t));
      }
    });
  }
}

/// Solidity at section-vertices (Def. 50; Property 2): around each vertex p, the kept
/// tetrahedra containing p, grouped by the faces through p they share, must each reach a
/// tetrahedron with a grounded triangle through p. (The thesis removes the T_vf fans that share
/// no face with a kept T_ee; where two planes meet, a fan also reaches p's ground through T_vf
/// tetrahedra grounded on the other plane, which this form of the condition keeps.)
/// Stars as (vertex, tetrahedron) pairs sorted: each vertex's kept tetrahedra, ascending.
/// Returns the tetrahedra to remove.
std::vector<int> ungroundedAtVertices(const CellComplex& c) {
  const std::size_t n = c.v.size();
  std::vector<std::pair<int, int>> stars;
  stars.reserve(4 * n);
  for (std::size_t t = 0; t < n; ++t)
    if (c.kept[t])
      for (const int p : c.v[t]) stars.emplace_back(p, int(t));
  std::sort(stars.begin(), stars.end());
  std::vector<int> remove, list;
  std::vector<std::uint8_t> grounded;
  DisjointSets groups(0);
  std::vector<int> where(n, -1);  // a tetrahedron's place in the current star's list
  for (std::size_t first = 0, last = 0; first < stars.size(); first = last) {
    const int p = stars[first].first;
    list.clear();
    for (last = first; last < stars.size() && stars[last].first == p; ++last) list.push_back(stars[last].second);
    groups.reset(list.size());
    for (std::size_t k = 0; k < list.size(); ++k) where[std::size_t(list[k])] = int(k);
    for (std::size_t k = 0; k < list.size(); ++k) {
      const std::size_t t = std::size_t(list[k]);
      for (int i = 0; i < 4; ++i) {
        const int o = c.nb[t][std::size_t(i)];  // through a face holding p: in p's star when kept
        if (c.v[t][std::size_t(i)] != p && o >= 0 && where[std::size_t(o)] >= 0)
          groups.unite(k, std::size_t(where[std::size_t(o)]));
      }
    }
    for (const int t : list) where[std::size_t(t)] = -1;
    grounded.assign(list.size(), 0);
    for (std::size_t k = 0; k < list.size(); ++k) {
      const std::size_t t = std::size_t(list[k]);
      for (int i = 0; i < 4; ++i)
        if (c.v[t][std::size_t(i)] != p && (c.grounded_faces[t] >> i & 1)) grounded[groups.find(k)] = 1;
    }
    for (std::size_t k = 0; k < list.size(); ++k)
      if (!grounded[groups.find(k)]) remove.push_back(list[k]);
  }
  return remove;
}

/// Step 3: tetrahedra not kept that share at least two faces with kept ones are added back (two
/// faces: only when their other edge is not in the solid yet), where they stay solid at their
/// grounded edges.
void growBack(CellComplex& c, ShellRoom& room) {
  const std::size_t n = c.v.size();
  const auto candidate = [&](std::size_t t) {
    return !c.kept[t] && !c.external[t] && !c.unjoined[t] && c.type[t] != TetType::flat &&
           (c.cycle_cut.empty() || !c.cycle_cut[t]);
  };
  std::deque<int> queue;
  std::vector<std::uint8_t> inQueue(n, 0);
  for (std::size_t t = 0; t < n; ++t)
    if (candidate(t)) {
      queue.push_back(int(t));
      inQueue[t] = 1;
    }
  while (!queue.empty()) {
    const std::size_t t = std::size_t(queue.front());
    queue.pop_front();
    inQueue[t] = 0;
    if (!candidate(t)) continue;
    int shared = 0, notShared[4], m = 0;
    for (int i = 0; i < 4; ++i) {
      const int o = c.nb[t][std::size_t(i)];
      if (o >= 0 && c.kept[std::size_t(o)]) ++shared;
      else notShared[m++] = i;
    }
    if (shared < 2) continue;
    if (shared == 2) {
      // The faces opposite i and j are not shared; the shared faces (opposite k and l) hold every
      // edge but (v_k, v_l): it must not be in the solid yet.
      const int i = notShared[0], j = notShared[1];
      int kl[2], q = 0;
      for (int x = 0; x < 4; ++x)
        if (x != i && x != j) kl[q++] = x;
      // The tetrahedra holding an edge are its shell (t is not kept yet).
      bool closed = false;
      shellOf(c, int(t), c.v[t][std::size_t(kl[0])], c.v[t][std::size_t(kl[1])], room.shell, room.scratch, &closed);
      if (std::any_of(room.shell.begin(), room.shell.end(), [&](int u) { return c.kept[std::size_t(u)] != 0; })) continue;
    }
    // Solidity at its grounded edges: around each, the tetrahedron must join a run that reaches a
    // grounded triangle through the edge, or it would hang there by an edge.
    c.kept[t] = 1;
    bool solid = true;
    for (int e = 0; e < 6; ++e) {
      const int a = c.v[t][std::size_t(kEdges[e][0])], b = c.v[t][std::size_t(kEdges[e][1])];
      if (!solid || !(c.grounded_edges[t] >> e & 1)) continue;
      bool closed = false;
      shellOf(c, int(t), a, b, room.shell, room.scratch, &closed);
      forEachRun(room.shell, closed, c.kept, room.run, [&](const std::vector<int>& r) {
        if (std::find(r.begin(), r.end(), int(t)) == r.end()) return;
        bool grounded = false;
        for (const int u : r)
          for (int i = 0; i < 4; ++i) {
            const int x = c.v[std::size_t(u)][std::size_t(i)];
            if (x != a && x != b && (c.grounded_faces[std::size_t(u)] >> i & 1)) grounded = true;
          }
        solid = grounded;
      });
    }
    if (!solid) {
      c.kept[t] = 0;
      continue;
    }
    for (const int o : c.nb[t])
      if (o >= 0 && candidate(std::size_t(o)) && !inQueue[std::size_t(o)]) {
        queue.push_back(o);
        inQueue[std::size_t(o)] = 1;
      }
  }
}

}  // namespace

void pruneCell(CellComplex& c) {
  const std::size_t n = c.v.size();
  c.kept.assign(n, 0);
  c.d1 = 0;
  for (std::size_t t = 0; t < n; ++t) {
    if (c.type[t] == TetType::flat || c.external[t] || c.unjoined[t] || (!c.cycle_cut.empty() && c.cycle_cut[t])) continue;
    ++c.d1;
    c.kept[t] = 1;
  }
  ShellRoom room;
  EdgeWork work(c);
  for (std::size_t t = 0; t < n; ++t)
    if (c.kept[t]) work.push(t);
  // Every grounded edge of a removed tetrahedron is re-examined.
  while (true) {
    pruneAtEdges(c, work, room);
    bool removed = false;
    for (const int t : ungroundedAtVertices(c))
      if (c.kept[std::size_t(t)]) {
        c.kept[std::size_t(t)] = 0;
        work.push(std::size_t(t));
        removed = true;
      }
    if (!removed) break;
  }
  c.d2 = std::count(c.kept.begin(), c.kept.end(), std::uint8_t(1));
  growBack(c, room);
  c.d3 = std::count(c.kept.begin(), c.kept.end(), std::uint8_t(1));
}

}  // namespace xsect
