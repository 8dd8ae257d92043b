// Per-cell comparison of a voxel solid with the connectivity graph (see cell_connectivity_check.h).
#include "geometry/cell_connectivity_check.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>

namespace xsect {
namespace {

struct SubSectionSeed {
  int node = -1;                  ///< section id (offset of its plane + section index)
  std::int64_t voxel = -1;        ///< a voxel of the solid in the cell beside the sub-section
};

struct CellWork {
  std::vector<std::int8_t> signs;  ///< the cell's sign vector against every plane
  std::vector<SubSectionSeed> seeds;
  bool unresolved = false;
};

}  // namespace

CellConnectivityCheck compareCellsWithVoxels(const std::vector<GraphEdge>& edges,
                                             const std::vector<CuttingPlane>& planes,
                                             const SectionArrangement& arr,
                                             const std::vector<SectionDistanceField>& fields,
                                             const std::vector<std::uint8_t>& inside,
                                             const GridSpec& grid) {
  const std::size_t P = planes.size();
  std::vector<int> offset(P + 1, 0);
  for (std::size_t i = 0; i < P; ++i) offset[i + 1] = offset[i] + int(planes[i].sections.size());
  const auto signOf = [&](std::size_t j, const Vec3& x) -> std::int8_t {
    const double s = planes[j].plane.signedDistance(x);
    return s > 0 ? 1 : (s < 0 ? -1 : 0);
  };
  const auto inCell = [&](const std::vector<std::int8_t>& signs, const Vec3& x) {
    for (std::size_t j = 0; j < P; ++j)
      if (signOf(j, x) != signs[j]) return false;
    return true;
  };

  // The deepest sample point of each sub-section, by (plane, section, cell): deepest inside the
  // section and away from the other planes' traces that bound the sub-section, so that a voxel
  // beside it is in the same cell.
  std::map<std::array<int, 3>, std::pair<float, const SectionPoint*>> deepest;
  for (const SectionPoint& sp : arr.points) {
    if (sp.kind != SectionPoint::sample || std::size_t(sp.plane) >= fields.size()) continue;
    float f = fields[std::size_t(sp.plane)].sample(sp.p.x(), sp.p.y());
    // Only a point deeper in its section than the best so far can be deeper overall.
    bool better = false;
    for (const int cell : sp.cell) {
      if (cell < 0) continue;
      const auto it = deepest.find({sp.plane, sp.section, cell});
      better = better || it == deepest.end() || f < it->second.first;
    }
    if (!better) continue;
    const Vec3 x = planes[std::size_t(sp.plane)].plane.toWorld(sp.p);
    for (std::size_t j = 0; j < P; ++j)
      if (j != std::size_t(sp.plane)) f = std::max(f, -float(std::abs(planes[j].plane.signedDistance(x))));
    for (const int cell : sp.cell) {
      if (cell < 0) continue;
      auto [it, fresh] = deepest.try_emplace({sp.plane, sp.section, cell}, f, &sp);
      if (!fresh && f < it->second.first) it->second = {f, &sp};
    }
  }
  std::vector<CellWork> cells(std::size_t(std::max(arr.cells, 0)));
  std::vector<char> hasSigns(cells.size(), 0);
  for (const SubSection& ss : arr.sub_sections) {
    if (ss.cell < 0 || std::size_t(ss.cell) >= cells.size()) continue;
    CellWork& c = cells[std::size_t(ss.cell)];
    const auto found = deepest.find({ss.plane, ss.section, ss.cell});
    SubSectionSeed seed;
    seed.node = offset[std::size_t(ss.plane)] + ss.section;
    if (found == deepest.end()) {
      c.unresolved = true;
      c.seeds.push_back(seed);
      continue;
    }
    const SectionPoint& sp = *found->second.second;
    const CuttingPlane& own = planes[std::size_t(ss.plane)];
    const Vec3 x0 = own.plane.toWorld(sp.p);
    // The seed point's side of every other plane, its own plane's side the sub-section's.
    std::vector<std::int8_t> signs(P);
    bool onTrace = false;
    for (std::size_t j = 0; j < P; ++j) {
      signs[j] = j == std::size_t(ss.plane) ? std::int8_t(ss.side) : signOf(j, x0);
      onTrace = onTrace || signs[j] == 0;
    }
    if (!hasSigns[std::size_t(ss.cell)] && !onTrace) {
      c.signs = signs;
      hasSigns[std::size_t(ss.cell)] = 1;
    }
    // A voxel of the solid, in the cell, just off the section on the cell's side.
    if (!onTrace)
      for (const double t : {0.6, 1.0, 1.5, 2.0}) {
        const Vec3 g = (x0 + double(ss.side) * t * grid.voxel * own.plane.normal - grid.origin) / grid.voxel;
        const int i = int(std::lround(g.x())), j = int(std::lround(g.y())), k = int(std::lround(g.z()));
        if (i < 0 || j < 0 || k < 0 || i >= grid.dims[0] || j >= grid.dims[1] || k >= grid.dims[2]) continue;
        const std::int64_t v = grid.index(i, j, k);
        if (!inside[std::size_t(v)] || !inCell(signs, grid.centre(i, j, k))) continue;
        seed.voxel = v;
        break;
      }
    c.unresolved = c.unresolved || seed.voxel < 0;
    c.seeds.push_back(seed);
  }

  // Components of the solid inside each cell (6-connected), from the seeds; parallel over cells:
  // a voxel has one sign vector, so no two cells write the same label.
  std::vector<int> component(inside.size(), -1);
  struct Result {
    bool compared = false, differs = false;
    int graphOnly = 0, voxelsOnly = 0;
  };
  std::vector<Result> results(cells.size());
  std::vector<std::vector<const GraphEdge*>> edgesOf(cells.size());
  for (const GraphEdge& e : edges)
    if (e.cell >= 0 && std::size_t(e.cell) < cells.size()) edgesOf[std::size_t(e.cell)].push_back(&e);
  tbb::parallel_for(std::size_t(0), cells.size(), [&](std::size_t ci) {
    CellWork& c = cells[ci];
    std::vector<int> nodes;
    for (const SubSectionSeed& s : c.seeds) nodes.push_back(s.node);
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    if (nodes.size() < 2 || c.unresolved || !hasSigns[ci]) return;
    // Voxel components from each seed.
    std::vector<std::int64_t> queue;
    for (std::size_t s = 0; s < c.seeds.size(); ++s) {
      const std::int64_t start = c.seeds[s].voxel;
      if (component[std::size_t(start)] >= 0) continue;
      component[std::size_t(start)] = int(s);
      queue.assign(1, start);
      std::vector<std::size_t> near;
      while (!queue.empty()) {
        const std::int64_t v = queue.back();
        queue.pop_back();
        const int i = int(v % grid.dims[0]), j = int((v / grid.dims[0]) % grid.dims[1]),
                  k = int(v / (std::int64_t(grid.dims[0]) * grid.dims[1]));
        // A neighbour one voxel away can be on the other side only of the planes within a voxel.
        const Vec3 x = grid.centre(i, j, k);
        near.clear();
        for (std::size_t p = 0; p < P; ++p)
          if (std::abs(planes[p].plane.signedDistance(x)) <= grid.voxel) near.push_back(p);
        const std::array<std::array<int, 3>, 6> steps{{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}};
        for (const auto& d : steps) {
          const int a = i + d[0], b = j + d[1], e = k + d[2];
          if (a < 0 || b < 0 || e < 0 || a >= grid.dims[0] || b >= grid.dims[1] || e >= grid.dims[2]) continue;
          const std::int64_t w = grid.index(a, b, e);
          if (!inside[std::size_t(w)]) continue;
          const Vec3 y = grid.centre(a, b, e);
          bool same = true;
          for (const std::size_t p : near) same = same && signOf(p, y) == c.signs[p];
          // own-cell voxels only: other cells' labels are written by other threads
          if (!same || component[std::size_t(w)] >= 0) continue;
          component[std::size_t(w)] = int(s);
          queue.push_back(w);
        }
      }
    }
    // The graph's classes in this cell.
    std::map<int, int> parent;
    for (const int n : nodes) parent[n] = n;
    const auto find = [&](int v) {
      while (parent[v] != v) v = parent[v] = parent[parent[v]];
      return v;
    };
    for (const GraphEdge* e : edgesOf[ci]) {
      const int a = offset[std::size_t(e->plane_a)] + e->section_a, b = offset[std::size_t(e->plane_b)] + e->section_b;
      if (!parent.count(a) || !parent.count(b)) continue;
      const int ra = find(a), rb = find(b);
      parent[std::max(ra, rb)] = std::min(ra, rb);
    }
    // A section's voxel classes: every component its sub-sections' seeds fall in (a section
    // bounds a cell once, but keep the smallest if it appears twice).
    std::map<int, int> voxelOf;
    for (const SubSectionSeed& s : c.seeds) {
      const int comp = component[std::size_t(s.voxel)];
      auto [it, fresh] = voxelOf.try_emplace(s.node, comp);
      if (!fresh) it->second = std::min(it->second, comp);
    }
    Result& r = results[ci];
    r.compared = true;
    for (std::size_t x = 0; x < nodes.size(); ++x)
      for (std::size_t y = x + 1; y < nodes.size(); ++y) {
        const bool g = find(nodes[x]) == find(nodes[y]);
        const bool v = voxelOf[nodes[x]] == voxelOf[nodes[y]];
        r.graphOnly += g && !v;
        r.voxelsOnly += v && !g;
      }
    r.differs = r.graphOnly + r.voxelsOnly > 0;
  });
  CellConnectivityCheck out;
  for (std::size_t ci = 0; ci < cells.size(); ++ci) {
    const Result& r = results[ci];
    std::vector<int> nodes;
    for (const SubSectionSeed& s : cells[ci].seeds) nodes.push_back(s.node);
    std::sort(nodes.begin(), nodes.end());
    const bool several = std::unique(nodes.begin(), nodes.end()) - nodes.begin() >= 2;
    if (!r.compared) {
      out.cells_unresolved += several;
      continue;
    }
    ++out.cells_compared;
    out.pairs_joined_by_graph_only += r.graphOnly;
    out.pairs_joined_by_voxels_only += r.voxelsOnly;
    if (r.differs) {
      ++out.cells_differing;
      if (out.differing_cells.size() < 20) out.differing_cells.push_back(int(ci));
    }
  }
  return out;
}

}  // namespace xsect
