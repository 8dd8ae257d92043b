// Method 3: cells, conformity, pruning and gluing (see delaunay_reconstruction.h); the repairs of
// the glued boundary are in boundary_repairs.h.
#include "geometry/delaunay/delaunay_reconstruction.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <functional>
#include <tuple>
#include <unordered_set>

#include "geometry/core/disjoint_sets.h"
#include "geometry/core/section_ids.h"
#include "geometry/delaunay/boundary_repairs.h"
#include "geometry/delaunay/cell_complex.h"
#include "geometry/delaunay/cell_cycles.h"
#include "geometry/delaunay/plane_gluing.h"
#include "geometry/delaunay/section_vertices.h"

namespace xsect {

namespace {

/// Rounds of contour splitting for Delaunay conformity; each halves the offending edges.
constexpr int kConformityRounds = 8;

struct CellSetup {
  std::vector<std::vector<int>> points;                 ///< per cell
  std::vector<std::vector<std::uint64_t>> contour;      ///< per cell: its contour edges
};

/// The points and contour edges of the cells flagged in `pending` (the others' lists stay empty:
/// after the first conformity round only the cells of split edges are triangulated again, 2 to 24
/// of multiaxial-3x40's 11 518, and listing every cell each round took random-800 about a second).
CellSetup cellSetup(const SectionVertices& sv, const std::vector<std::uint8_t>& pending) {
  CellSetup s;
  s.points.resize(std::size_t(sv.cells));
  s.contour.resize(std::size_t(sv.cells));
  const auto wanted = [&](int c) { return c >= 0 && c < sv.cells && pending[std::size_t(c)]; };
  for (std::size_t id = 0; id < sv.points.size(); ++id)
    for (const PointCell& c : sv.points[id].cells)
      if (wanted(c.cell)) s.points[std::size_t(c.cell)].push_back(int(id));
  for (const SampledRing& r : sv.rings)
    for (std::size_t k = 0; k < r.points.size(); ++k) {
      const int a = r.points[k], b = r.points[(k + 1) % r.points.size()];
      // A contour edge lies in cells of both its ends: none pending at one end, none for the edge.
      const auto& ca = sv.points[std::size_t(a)].cells;
      if (std::none_of(ca.begin(), ca.end(), [&](const PointCell& c) { return wanted(c.cell); })) continue;
      for (const int c : edgeCells(sv, a, b, r.plane))
        if (wanted(c)) s.contour[std::size_t(c)].push_back(edgeKey(a, b));
    }
  return s;
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

/// Per section-vertex, the component of G'' (`joinable`, Def. 44) holding its section
/// (`sectionOf`: flat ids of `ids`), for markUnjoined. Sections that touch (a point on the
/// contours of both: a trace point where two contours cross; a corner inside sections of three
/// planes) are one object whatever the lattice of G'' saw; a section G'' joins to none gives no
/// evidence either way: its points get -1 (they join anything), as do points of no section.
/// `sampled`: the locators of sv.sampled, one per plane.
std::vector<int> pointComponents(const SectionVertices& sv, const std::vector<CuttingPlane>& planes,
                                 const std::vector<SectionLocator>& sampled, const SectionIds& ids,
                                 const std::vector<int>& sectionOf, const std::vector<GraphEdge>& joinable) {
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

/// The glued boundary of R'' (ch. 3 §2.4): every cell's non-grounded boundary faces and each
/// plane's flat faces, repaired (boundary_repairs.h). Writes out.mesh, out.tolerances and the
/// boundary's counts in out.stats (flat_faces, constraint_crossings, welded_vertices,
/// holes_closed, flat_shells_dropped, singular_edges, singular_vertices, open_edges); nothing else
/// of `out`.
void glueBoundary(const std::vector<CuttingPlane>& planes, const SectionArrangement& arr, const SectionVertices& sv,
                  const std::vector<CellComplex>& cx, DelaunayReconstruction& out) {
  const std::size_t cells = cx.size();
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
  out.tolerances = {1e-2 * arr.sample_spacing_mm, 1e-3 * arr.sample_spacing_mm};
  out.stats.welded_vertices = weldNearVertices(faces, positions, out.tolerances.weld_mm, [&](int id) {
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
  // An open one only below a square of the sample spacing (the one measured: 5e-4 mm² against
  // 0.3 mm spacing).
  out.stats.flat_shells_dropped = dropFlatShells(faces, positions, out.tolerances.flat_thickness_mm,
                                                 arr.sample_spacing_mm * arr.sample_spacing_mm);
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
}

/// The tetrahedra of D3 on the section-vertices they use, the connections they realise, and the
/// counts of D0-D3 per type. Writes out.tetrahedra, out.connections and those counts in
/// out.stats (cells, d0, d1-d3, external, unjoined); nothing else of `out`.
void tallyTetrahedra(const SectionVertices& sv, const std::vector<CellComplex>& cx, const std::vector<int>& sectionOf,
                     const SectionIds& ids, DelaunayReconstruction& out) {
  const std::size_t cells = cx.size();
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
      for (const auto& e : kEdges) {
        const std::size_t a = std::size_t(C.v[t][std::size_t(e[0])]), b = std::size_t(C.v[t][std::size_t(e[1])]);
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
}

}  // namespace

DelaunayReconstruction delaunayReconstruction(const std::vector<CuttingPlane>& planes, const SectionArrangement& arr,
                                              const std::vector<BranchingPoint>& branching,
                                              const std::function<void(std::int64_t, std::int64_t)>& progress,
                                              const std::vector<GraphEdge>* joinable, CellTunnels tunnels) {
  DelaunayReconstruction out;
  SectionVertices sv = sectionVertices(planes, arr, branching);
  const std::size_t cells = std::size_t(sv.cells);
  out.stats.cells_unseen = sv.cells - arr.cells;
  out.stats.rings_dropped = sv.rings_dropped;
  std::vector<CellComplex> cx(cells);
  std::vector<std::uint8_t> pending(cells, 1);
  std::unordered_set<std::uint64_t> contour = contourEdges(sv);
  // D0 with Delaunay conformity: contour edges that are not Delaunay edges are split at their
  // midpoints (in both cells they bound) until all are, or the rounds run out.
  // Step 1's containment tests, per plane: of the sections as the last round left them (the loop
  // ends before resampling them again).
  std::vector<SectionLocator> sampled;
  sampled.reserve(sv.sampled.size());
  for (int round = 0; round < kConformityRounds; ++round) {
    const CellSetup setup = cellSetup(sv, pending);
    sampled.clear();
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
    const std::vector<int> partOf = pointComponents(sv, planes, sampled, ids, sectionOf, *joinable);
    tbb::parallel_for(std::size_t(0), cells, [&](std::size_t c) { markUnjoined(cx[c], partOf); });
  }
  // Steps 2 and 3 in every cell.
  std::vector<CellCycleCuts> cycleCuts(cells);
  tbb::parallel_for(std::size_t(0), cells, [&](std::size_t c) {
    pruneCell(cx[c]);
    if (tunnels == CellTunnels::cut) cycleCuts[c] = cutCellCycles(cx[c], sectionOf, sv.points);
  });
  for (const CellCycleCuts& n : cycleCuts) {
    out.stats.cell_pairs_cut += n.pairs;
    out.stats.cell_tunnels_cut += n.tunnels;
    out.stats.cell_tetrahedra_cut += n.tetrahedra;
  }
  if (progress) progress(std::int64_t(cells), std::int64_t(cells));

  // The glued boundary and the tallies of the tetrahedra read the cells only and write different
  // members of `out`: side by side (each has serial stretches; multiaxial-3x40: 0.75 s and 0.17 s
  // one after the other).
  tbb::parallel_invoke([&] { glueBoundary(planes, arr, sv, cx, out); },
                       [&] { tallyTetrahedra(sv, cx, sectionOf, ids, out); });
  for (const SectionVertex& v : sv.points) out.stats.branching_points += v.kind == SectionVertex::branching && !v.cells.empty();
  // A point counts once per cell it lies in (what cellSetup lists in the first round), without
  // listing them again.
  for (const SectionVertex& v : sv.points)
    for (const PointCell& c : v.cells) out.stats.section_vertices += c.cell >= 0 && c.cell < sv.cells;
  return out;
}

}  // namespace xsect
