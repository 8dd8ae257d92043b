// Connectivity graphs G and G' along the lifts of section points (see connectivity_graph.h).
#include "geometry/arrangement/connectivity_graph.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <functional>
#include <limits>
#include <memory>
#include <numeric>
#include <tuple>

#include "geometry/core/digital_topology.h"
#include "geometry/core/disjoint_sets.h"
#include "geometry/core/polygon.h"
#include "geometry/core/section_ids.h"
#include "geometry/core/section_locator.h"

namespace xsect {

bool GraphEdge::operator<(const GraphEdge& o) const {
  return std::tie(cell, plane_a, section_a, plane_b, section_b) <
         std::tie(o.cell, o.plane_a, o.section_a, o.plane_b, o.section_b);
}
bool GraphEdge::operator==(const GraphEdge& o) const {
  return std::tie(cell, plane_a, section_a, plane_b, section_b) ==
         std::tie(o.cell, o.plane_a, o.section_a, o.plane_b, o.section_b);
}

namespace {

/// The section of plane cp holding x (its projection), or -1.
int sectionAt(const CuttingPlane& cp, const SectionLocator& locator, const Vec3& x) {
  return locator.holding(cp.plane.toPlane(x));
}

GraphEdge edge(int pa, int sa, int pb, int sb, int cell) {
  if (std::tie(pb, sb) < std::tie(pa, sa)) {
    std::swap(pa, pb);
    std::swap(sa, sb);
  }
  return {pa, sa, pb, sb, cell};
}

}  // namespace

ConnectivityGraphs connectivityGraphs(const SectionScene& scene, const SectionArrangement& arr,
                                      const SectionVoronoiParams& method2, bool withGPrime) {
  const std::vector<CuttingPlane>& planes = scene.planes;
  const std::vector<SectionDistanceField>& fields = scene.fields;
  std::unique_ptr<SectionVoronoiPoints> query;
  if (withGPrime) query = std::make_unique<SectionVoronoiPoints>(planes, fields, method2);
  const double step = arr.sample_spacing_mm;
  std::vector<SectionLocator> locators;
  locators.reserve(planes.size());
  for (const CuttingPlane& p : planes) locators.emplace_back(p.sections);
  // Per section: the other planes by distance to its bounding disk. A plane at distance >= 2t
  // from a section point cannot end the lift of length t (|h + t c| = t needs |h| <= 2t), nor
  // bound the ray's exit below |h|: the scan stops at the first plane too far for both.
  const SectionIds ids = scene.ids();
  std::vector<std::vector<std::pair<double, int>>> nearPlanes(std::size_t(ids.count()));
  tbb::parallel_for(std::size_t(0), planes.size(), [&](std::size_t i) {
    for (std::size_t s = 0; s < planes[i].sections.size(); ++s) {
      const Eigen::AlignedBox2d& b = locators[i].boxes()[s];
      const Vec3 c = planes[i].plane.toWorld(b.center());
      const double rad = 0.5 * b.diagonal().norm() + 1e-9;
      auto& L = nearPlanes[std::size_t(ids.of(int(i), int(s)))];
      for (std::size_t j = 0; j < planes.size(); ++j)
        if (j != i) L.push_back({std::abs(planes[j].plane.signedDistance(c)) - rad, int(j)});
      std::sort(L.begin(), L.end());
    }
  });
  tbb::enumerable_thread_specific<ConnectivityGraphs> local;
  tbb::parallel_for(std::size_t(0), arr.points.size(), [&](std::size_t q) {
    const SectionPoint& sp = arr.points[q];
    if (sp.kind == SectionPoint::trace) return;
    ConnectivityGraphs& out = local.local();
    const CuttingPlane& P = planes[std::size_t(sp.plane)];
    const Vec3 a = P.plane.toWorld(sp.p);
    SectionVoronoiPoints::CellMemo memo;
    for (int side = 0; side < 2; ++side) {
      const Vec3 n = (side == 0 ? -1.0 : 1.0) * P.plane.normal;
      const int cell = sp.cell[std::size_t(side)];
      // Method 1: first t > 0 with d(a + t n, Q) = t for some other plane Q; the ray leaves the
      // cell (crosses Q) only after that.
      double best = std::numeric_limits<double>::infinity(), exit = best;
      int bq = -1;
      for (const auto& [lb, jj] : nearPlanes[std::size_t(ids.of(sp.plane, sp.section))]) {
        if (lb >= std::max(2 * best, exit)) break;
        const std::size_t j = std::size_t(jj);
        const double hq = planes[j].plane.signedDistance(a), c = planes[j].plane.normal.dot(n);
        for (const double t : {c != 1 ? hq / (1 - c) : -1.0, c != -1 ? -hq / (1 + c) : -1.0})
          if (t > 1e-9 && t < best) {
            best = t;
            bq = int(j);
          }
        if (c != 0 && -hq / c > 0) exit = std::min(exit, -hq / c);
      }
      if (bq >= 0) {
        const int b = sectionAt(planes[std::size_t(bq)], locators[std::size_t(bq)], a + best * n);
        if (b >= 0) out.g.push_back(edge(sp.plane, sp.section, bq, b, cell));
      }
      if (!query) continue;
      // Method 2: the ray from a lies in A's lift up to method 1's lift point (proof of Theorem
      // 18), where lift'(a) = lift(a) whenever that point projects into a section. From there on
      // it is followed at evenly spaced points (at least one before it leaves the cell), starting
      // just beyond lift(a), while it stays in A's lift.
      const double from = std::min(best, exit);
      std::vector<double> ts;
      if (best < exit) ts.push_back(best * (1 + 1e-9) + 1e-9);
      const int m = std::max(1, std::min(4096, int(std::ceil((exit - from) / step))));
      if (std::isfinite(exit))
        for (int q2 = 0; q2 < m; ++q2) ts.push_back(from + (exit - from) * (q2 + 0.5) / m);
      memo.radius = -1;  // the ray's points lie in one cell: it is clipped once
      for (const double t : ts) {
        const Vec3 x = a + t * n;
        const SectionVoronoiPoints::Answer ans = query->at(x, &memo);
        if (!ans.inside) break;
        if (ans.section_plane == sp.plane) continue;
        const int b = sectionAt(planes[std::size_t(ans.section_plane)], locators[std::size_t(ans.section_plane)], x);
        if (b >= 0) out.g_prime.push_back(edge(sp.plane, sp.section, ans.section_plane, b, cell));
        break;
      }
    }
  });
  ConnectivityGraphs all;
  for (auto& l : local) {
    all.g.insert(all.g.end(), l.g.begin(), l.g.end());
    all.g_prime.insert(all.g_prime.end(), l.g_prime.begin(), l.g_prime.end());
  }
  for (auto* v : {&all.g, &all.g_prime}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  return all;
}

GraphVoxelCheck compareWithVoxels(const std::vector<GraphEdge>& edges, const SectionScene& scene,
                                  const SectionArrangement& arrangement, const std::vector<std::uint8_t>& inside,
                                  const GridSpec& grid) {
  return compareWithVoxels(edges, scene, arrangement, solidComponentIndex(inside, grid));
}

GraphVoxelCheck compareWithVoxels(const std::vector<GraphEdge>& edges, const SectionScene& scene,
                                  const SectionArrangement& arrangement, const BlockGrid<std::uint8_t>& inside) {
  return compareWithVoxels(edges, scene, arrangement, solidComponentIndex(inside));
}

GraphVoxelCheck compareWithVoxels(const std::vector<GraphEdge>& edges, const SectionScene& scene,
                                  const SectionArrangement& arr, const SolidComponentIndex& solid) {
  const GridSpec& grid = solid.grid;
  const std::vector<CuttingPlane>& planes = scene.planes;
  const std::vector<SectionDistanceField>& fields = scene.fields;
  const SectionIds ids = scene.ids();
  const int n = ids.count();
  DisjointSets components{std::size_t(n)};
  for (const GraphEdge& e : edges)
    components.unite(std::size_t(ids.of(e.plane_a, e.section_a)), std::size_t(ids.of(e.plane_b, e.section_b)));
  const auto find = [&](int s) { return int(components.find(std::size_t(s))); };
  // The deepest lattice point of each section, and the voxel holding it.
  std::vector<float> depth(std::size_t(n), 0.f);
  std::vector<Vec3> where(std::size_t(n), Vec3::Zero());
  for (const SectionPoint& sp : arr.points) {
    if (sp.kind != SectionPoint::sample || std::size_t(sp.plane) >= fields.size()) continue;
    const int id = ids.of(sp.plane, sp.section);
    const float f = fields[std::size_t(sp.plane)].sample(sp.p.x(), sp.p.y());
    if (f < depth[std::size_t(id)]) {
      depth[std::size_t(id)] = f;
      where[std::size_t(id)] = planes[std::size_t(sp.plane)].plane.toWorld(sp.p);
    }
  }
  std::vector<int> voxel(std::size_t(n), -1);
  GraphVoxelCheck r;
  for (int s = 0; s < n; ++s) {
    if (depth[std::size_t(s)] >= 0) {
      ++r.sections_unlocated;
      continue;
    }
    const Vec3 g = (where[std::size_t(s)] - grid.origin) / grid.voxel;
    const int i = int(std::lround(g.x())), j = int(std::lround(g.y())), k = int(std::lround(g.z()));
    if (i < 0 || j < 0 || k < 0 || i >= grid.dims[0] || j >= grid.dims[1] || k >= grid.dims[2] ||
        solid.at(i, j, k) < 0) {
      ++r.sections_unlocated;
      continue;
    }
    voxel[std::size_t(s)] = solid.at(i, j, k);
  }
  std::vector<int> roots, labels;
  for (int s = 0; s < n; ++s) {
    roots.push_back(find(s));
    if (voxel[std::size_t(s)] >= 0) labels.push_back(voxel[std::size_t(s)]);
  }
  std::sort(roots.begin(), roots.end());
  std::sort(labels.begin(), labels.end());
  r.graph_components = int(std::unique(roots.begin(), roots.end()) - roots.begin());
  r.voxel_components = int(std::unique(labels.begin(), labels.end()) - labels.begin());
  for (int s = 0; s < n; ++s)
    for (int t = s + 1; t < n; ++t) {
      if (voxel[std::size_t(s)] < 0 || voxel[std::size_t(t)] < 0) continue;
      const bool g = find(s) == find(t), v = voxel[std::size_t(s)] == voxel[std::size_t(t)];
      r.pairs_joined_by_graph_only += g && !v;
      r.pairs_joined_by_voxels_only += v && !g;
    }
  r.same_partition = r.pairs_joined_by_graph_only == 0 && r.pairs_joined_by_voxels_only == 0;
  return r;
}

}  // namespace xsect
