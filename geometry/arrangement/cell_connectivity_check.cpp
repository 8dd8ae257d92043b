// Per-cell comparison of a voxel solid with the connectivity graph (see cell_connectivity_check.h).
#include "geometry/arrangement/cell_connectivity_check.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>

#include "geometry/core/disjoint_sets.h"
#include "geometry/core/section_ids.h"

namespace xsect {
namespace {

struct Seed {
  int node = -1;             ///< section id (offset of its plane + section index)
  std::int64_t voxel = -1;   ///< a voxel of the solid in the cell, beside the section
};

struct CellWork {
  std::vector<std::int8_t> signs;  ///< the cell's sign vector against every plane (empty: none)
  std::vector<Seed> seeds;
  std::vector<int> nodes;          ///< the sections bounding the cell
  bool unresolved = false;
};

}  // namespace

CellConnectivityCheck compareCellsWithVoxels(const std::vector<GraphEdge>& edges, const SectionScene& scene,
                                             const SectionArrangement& arr,
                                             const std::vector<std::uint8_t>& inside, const GridSpec& grid,
                                             const std::vector<int>& only_cells, double seed_mm) {
  const std::vector<CuttingPlane>& planes = scene.planes;
  const std::vector<SectionDistanceField>& fields = scene.fields;
  const std::size_t P = planes.size();
  const auto wanted = [&](int cell) {
    return cell >= 0 && (only_cells.empty() || std::binary_search(only_cells.begin(), only_cells.end(), cell));
  };
  const double h = grid.voxel;
  const double hs = seed_mm > 0 ? seed_mm : h;  // seeds: how deep, and how far off the section
  const SectionIds ids(planes);
  const auto signOf = [&](std::size_t j, const Vec3& x) -> std::int8_t {
    const double s = planes[j].plane.signedDistance(x);
    return s > 0 ? 1 : (s < 0 ? -1 : 0);
  };
  const auto inCell = [&](const std::vector<std::int8_t>& signs, const Vec3& x) {
    for (std::size_t j = 0; j < P; ++j)
      if (signOf(j, x) != signs[j]) return false;
    return true;
  };
  /// Depth of a section point in its sub-section: into the section and away from the other
  /// planes (whose traces bound the sub-section); negative inside, mm.
  const auto depthOf = [&](const SectionPoint& sp, float contour) {
    float f = contour;
    const Vec3 x = planes[std::size_t(sp.plane)].plane.toWorld(sp.p);
    for (std::size_t j = 0; j < P; ++j)
      if (j != std::size_t(sp.plane)) f = std::max(f, -float(std::abs(planes[j].plane.signedDistance(x))));
    return f;
  };

  // Per sub-section (plane, section, cell): its deepest sample point, and every sample point at
  // least a voxel deep (seeds all over it: a sub-section may touch several components).
  struct Points {
    float depth = 0;
    const SectionPoint* deepest = nullptr;
    std::vector<const SectionPoint*> deep;
  };
  std::map<std::array<int, 3>, Points> points;
  for (const SectionPoint& sp : arr.points) {
    if (sp.kind != SectionPoint::sample || std::size_t(sp.plane) >= fields.size()) continue;
    if (!wanted(sp.cell[0]) && !wanted(sp.cell[1])) continue;
    const float contour = fields[std::size_t(sp.plane)].sample(sp.p.x(), sp.p.y());
    bool better = contour <= -hs;  // a candidate seed; else only a candidate deepest point
    for (const int cell : sp.cell) {
      if (!wanted(cell)) continue;
      const auto it = points.find({sp.plane, sp.section, cell});
      better = better || it == points.end() || contour < it->second.depth;
    }
    if (!better) continue;
    const float f = depthOf(sp, contour);
    for (const int cell : sp.cell) {
      if (!wanted(cell)) continue;
      Points& p = points[{sp.plane, sp.section, cell}];
      if (!p.deepest || f < p.depth) p.depth = f, p.deepest = &sp;
      if (f <= -hs) p.deep.push_back(&sp);
    }
  }

  std::vector<CellWork> cells(std::size_t(std::max(arr.cells, 0)));
  for (const SubSection& ss : arr.sub_sections) {
    if (!wanted(ss.cell) || std::size_t(ss.cell) >= cells.size()) continue;
    CellWork& c = cells[std::size_t(ss.cell)];
    const int node = ids.of(ss.plane, ss.section);
    c.nodes.push_back(node);
    const auto found = points.find({ss.plane, ss.section, ss.cell});
    if (found == points.end()) {
      c.unresolved = true;  // no sample point: a sliver of a section
      continue;
    }
    const CuttingPlane& own = planes[std::size_t(ss.plane)];
    std::vector<const SectionPoint*> from = found->second.deep;
    if (from.empty()) from.push_back(found->second.deepest);
    for (const SectionPoint* sp : from) {
      const Vec3 x0 = own.plane.toWorld(sp->p);
      // The point's side of every other plane, its own plane's side the sub-section's.
      std::vector<std::int8_t> signs(P);
      bool onTrace = false;
      for (std::size_t j = 0; j < P; ++j) {
        signs[j] = j == std::size_t(ss.plane) ? std::int8_t(ss.side) : signOf(j, x0);
        onTrace = onTrace || signs[j] == 0;
      }
      if (onTrace) {
        c.unresolved = true;
        break;
      }
      if (c.signs.empty()) c.signs = signs;
      // A voxel of the solid, in the cell, just off the section on the cell's side.
      std::int64_t voxel = -1;
      for (const double t : {0.6, 1.0}) {
        const Vec3 g = (x0 + double(ss.side) * t * hs * own.plane.normal - grid.origin) / h;
        const int i = int(std::lround(g.x())), j = int(std::lround(g.y())), k = int(std::lround(g.z()));
        if (i < 0 || j < 0 || k < 0 || i >= grid.dims[0] || j >= grid.dims[1] || k >= grid.dims[2]) continue;
        const std::int64_t v = grid.index(i, j, k);
        if (!inside[std::size_t(v)] || !inCell(c.signs, grid.centre(i, j, k))) continue;
        voxel = v;
        break;
      }
      if (voxel < 0) {  // the solid misses the section here, or the cell is thinner than a voxel
        c.unresolved = true;
        break;
      }
      c.seeds.push_back({node, voxel});
    }
  }

  // Components of the solid inside each cell (6-connected), from the seeds; parallel over cells.
  // A voxel belongs to one cell, and a fill only enters voxels of its own cell: a neighbour one
  // voxel away can be on the other side only of the planes within a voxel of the current centre
  // (with a margin for rounding), and those are tested exactly. So no two cells touch the same
  // label.
  std::vector<int> component(inside.size(), -1);
  struct Result {
    bool compared = false;
    int graphOnly = 0, voxelsOnly = 0;
  };
  std::vector<Result> results(cells.size());
  std::vector<std::vector<const GraphEdge*>> edgesOf(cells.size());
  for (const GraphEdge& e : edges)
    if (e.cell >= 0 && std::size_t(e.cell) < cells.size()) edgesOf[std::size_t(e.cell)].push_back(&e);
  tbb::parallel_for(std::size_t(0), cells.size(), [&](std::size_t ci) {
    CellWork& c = cells[ci];
    std::sort(c.nodes.begin(), c.nodes.end());
    c.nodes.erase(std::unique(c.nodes.begin(), c.nodes.end()), c.nodes.end());
    if (c.nodes.size() < 2 || c.unresolved || c.signs.empty()) return;
    std::vector<std::int64_t> queue;
    std::vector<std::size_t> near;
    for (std::size_t s = 0; s < c.seeds.size(); ++s) {
      const std::int64_t start = c.seeds[s].voxel;
      if (component[std::size_t(start)] >= 0) continue;
      component[std::size_t(start)] = int(s);
      queue.assign(1, start);
      while (!queue.empty()) {
        const std::int64_t v = queue.back();
        queue.pop_back();
        const int i = int(v % grid.dims[0]), j = int((v / grid.dims[0]) % grid.dims[1]),
                  k = int(v / (std::int64_t(grid.dims[0]) * grid.dims[1]));
        const Vec3 x = grid.centre(i, j, k);
        near.clear();
        for (std::size_t p = 0; p < P; ++p)
          if (std::abs(planes[p].plane.signedDistance(x)) <= h * (1 + 1e-6) + 1e-9) near.push_back(p);
        const std::array<std::array<int, 3>, 6> steps{{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}};
        for (const auto& d : steps) {
          const int a = i + d[0], b = j + d[1], e = k + d[2];
          if (a < 0 || b < 0 || e < 0 || a >= grid.dims[0] || b >= grid.dims[1] || e >= grid.dims[2]) continue;
          const std::int64_t w = grid.index(a, b, e);
          if (!inside[std::size_t(w)]) continue;
          const Vec3 y = grid.centre(a, b, e);
          bool same = true;
          for (const std::size_t p : near) same = same && signOf(p, y) == c.signs[p];
          if (!same || component[std::size_t(w)] >= 0) continue;
          component[std::size_t(w)] = int(s);
          queue.push_back(w);
        }
      }
    }
    // The classes of the cell's sections (by their place in c.nodes, sorted and unique): the
    // solid's, sections touching one component together; the graph's, from its edges in the cell.
    const auto place = [&](int node) {
      return std::size_t(std::lower_bound(c.nodes.begin(), c.nodes.end(), node) - c.nodes.begin());
    };
    DisjointSets solid(c.nodes.size()), graph(c.nodes.size());
    std::map<int, int> ownerOf;  // component -> a section touching it
    for (const Seed& s : c.seeds) {
      const auto [it, fresh] = ownerOf.try_emplace(component[std::size_t(s.voxel)], s.node);
      if (!fresh) solid.unite(place(s.node), place(it->second));
    }
    for (const GraphEdge* e : edgesOf[ci]) {
      const int a = ids.of(e->plane_a, e->section_a), b = ids.of(e->plane_b, e->section_b);
      if (std::binary_search(c.nodes.begin(), c.nodes.end(), a) && std::binary_search(c.nodes.begin(), c.nodes.end(), b))
        graph.unite(place(a), place(b));
    }
    Result& r = results[ci];
    r.compared = true;
    for (std::size_t x = 0; x < c.nodes.size(); ++x)
      for (std::size_t y = x + 1; y < c.nodes.size(); ++y) {
        const bool g = graph.find(x) == graph.find(y);
        const bool v = solid.find(x) == solid.find(y);
        r.graphOnly += g && !v;
        r.voxelsOnly += v && !g;
      }
  });
  CellConnectivityCheck out;
  out.pairs_by_cell.assign(cells.size(), -1);
  for (std::size_t ci = 0; ci < cells.size(); ++ci) {
    const Result& r = results[ci];
    if (!r.compared) {
      out.cells_unresolved += cells[ci].nodes.size() >= 2;
      continue;
    }
    ++out.cells_compared;
    out.pairs_by_cell[ci] = r.graphOnly + r.voxelsOnly;
    out.pairs_joined_by_graph_only += r.graphOnly;
    out.pairs_joined_by_voxels_only += r.voxelsOnly;
    if (r.graphOnly + r.voxelsOnly > 0) {
      ++out.cells_differing;
      if (out.differing_cells.size() < 20) out.differing_cells.push_back(int(ci));
    }
  }
  return out;
}

std::vector<int> cellsDifferingMore(const CellConnectivityCheck& solid, const CellConnectivityCheck& reference) {
  std::vector<int> out;
  const std::size_t n = std::min(solid.pairs_by_cell.size(), reference.pairs_by_cell.size());
  for (std::size_t c = 0; c < n; ++c)
    if (solid.pairs_by_cell[c] >= 0 && reference.pairs_by_cell[c] >= 0 &&
        solid.pairs_by_cell[c] > reference.pairs_by_cell[c])
      out.push_back(int(c));
  return out;
}

bool keepsCellConnectivity(const CellConnectivityCheck& solid, const CellConnectivityCheck& reference) {
  return cellsDifferingMore(solid, reference).empty();
}

}  // namespace xsect
