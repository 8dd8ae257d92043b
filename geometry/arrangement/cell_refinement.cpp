// Cells re-compared on finer lattices (see cell_refinement.h).
#include "geometry/arrangement/cell_refinement.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace xsect {
namespace {

/// The cell's sign vector against every plane, from one of its section points off every other
/// plane (the point's own plane: the side the cell lies on); empty when it has none.
std::vector<std::int8_t> signsOfCell(int cell, const std::vector<CuttingPlane>& planes,
                                     const SectionArrangement& arr) {
  for (const SectionPoint& sp : arr.points) {
    if (sp.kind == SectionPoint::trace || std::size_t(sp.plane) >= planes.size()) continue;
    for (int side = 0; side < 2; ++side) {
      if (sp.cell[std::size_t(side)] != cell) continue;
      const Vec3 x = planes[std::size_t(sp.plane)].plane.toWorld(sp.p);
      std::vector<std::int8_t> signs(planes.size());
      bool off = true;
      for (std::size_t j = 0; j < planes.size() && off; ++j) {
        const double d = planes[j].plane.signedDistance(x);
        signs[j] = int(j) == sp.plane ? std::int8_t(side ? 1 : -1) : std::int8_t(d > 0 ? 1 : (d < 0 ? -1 : 0));
        off = signs[j] != 0;
      }
      if (off) return signs;
    }
  }
  return {};
}

bool inCell(const Vec3& x, const std::vector<std::int8_t>& signs, const std::vector<CuttingPlane>& planes) {
  for (std::size_t p = 0; p < planes.size(); ++p) {
    const double d = planes[p].plane.signedDistance(x);
    if ((d > 0 ? 1 : (d < 0 ? -1 : 0)) != signs[p]) return false;
  }
  return true;
}

/// Box (grid indices, inclusive) of the grid's voxel centres in the cell: those 26-connected,
/// within the cell, to the centres near its section points. Empty when none is found, or when the
/// box grows past `widest` voxels along an axis (its lattices would be too large to evaluate).
std::optional<std::array<int, 6>> cellBox(int cell, const std::vector<std::int8_t>& signs,
                                          const std::vector<CuttingPlane>& planes,
                                          const SectionArrangement& arr, const GridSpec& grid,
                                          std::int64_t widest) {
  const auto inCellAt = [&](int i, int j, int k) { return inCell(grid.centre(i, j, k), signs, planes); };
  const auto inGrid = [&](int i, int j, int k) {
    return i >= 0 && j >= 0 && k >= 0 && i < grid.dims[0] && j < grid.dims[1] && k < grid.dims[2];
  };
  std::vector<std::int64_t> queue;
  for (const SectionPoint& sp : arr.points) {
    if (sp.cell[0] != cell && sp.cell[1] != cell) continue;
    const Vec3 g = (planes[std::size_t(sp.plane)].plane.toWorld(sp.p) - grid.origin) / grid.voxel;
    const int i0 = int(std::floor(g.x())), j0 = int(std::floor(g.y())), k0 = int(std::floor(g.z()));
    for (int k = k0 - 1; k <= k0 + 2; ++k)
      for (int j = j0 - 1; j <= j0 + 2; ++j)
        for (int i = i0 - 1; i <= i0 + 2; ++i)
          if (inGrid(i, j, k)) queue.push_back(grid.index(i, j, k));
  }
  std::sort(queue.begin(), queue.end());
  queue.erase(std::unique(queue.begin(), queue.end()), queue.end());
  const auto ijk = [&](std::int64_t v) {
    return std::array<int, 3>{int(v % grid.dims[0]), int((v / grid.dims[0]) % grid.dims[1]),
                              int(v / (std::int64_t(grid.dims[0]) * grid.dims[1]))};
  };
  queue.erase(std::remove_if(queue.begin(), queue.end(),
                             [&](std::int64_t v) {
                               const auto c = ijk(v);
                               return !inCellAt(c[0], c[1], c[2]);
                             }),
              queue.end());
  if (queue.empty()) return std::nullopt;
  std::vector<std::uint8_t> visited;  // over the grid: cells to refine are few, the grid is dense anyway
  visited.assign(std::size_t(grid.count()), 0);
  for (const std::int64_t v : queue) visited[std::size_t(v)] = 1;
  std::array<int, 6> box{grid.dims[0], grid.dims[1], grid.dims[2], -1, -1, -1};
  while (!queue.empty()) {
    const std::int64_t v = queue.back();
    queue.pop_back();
    const auto c = ijk(v);
    for (int a = 0; a < 3; ++a) {
      box[std::size_t(a)] = std::min(box[std::size_t(a)], c[std::size_t(a)]);
      box[std::size_t(a + 3)] = std::max(box[std::size_t(a + 3)], c[std::size_t(a)]);
      if (box[std::size_t(a + 3)] - box[std::size_t(a)] > widest) return std::nullopt;
    }
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int i = c[0] + di, j = c[1] + dj, k = c[2] + dk;
          if (!inGrid(i, j, k)) continue;
          const std::int64_t w = grid.index(i, j, k);
          if (visited[std::size_t(w)] || !inCellAt(i, j, k)) continue;
          visited[std::size_t(w)] = 1;
          queue.push_back(w);
        }
  }
  return box;
}

/// Whether the solid has a voxel in the cell on the outer layer of the lattice `box`.
bool reachesOuterLayer(const std::vector<std::uint8_t>& inside, const GridSpec& box,
                       const std::vector<std::int8_t>& signs, const std::vector<CuttingPlane>& planes) {
  for (int k = 0; k < box.dims[2]; ++k)
    for (int j = 0; j < box.dims[1]; ++j)
      for (int i = 0; i < box.dims[0]; ++i) {
        const bool outer = i == 0 || j == 0 || k == 0 || i + 1 == box.dims[0] || j + 1 == box.dims[1] ||
                           k + 1 == box.dims[2];
        if (outer && inside[std::size_t(box.index(i, j, k))] && inCell(box.centre(i, j, k), signs, planes))
          return true;
      }
  return false;
}

}  // namespace

std::vector<CellRefinement> refineCellComparison(
    const std::vector<int>& cells, const CellConnectivityCheck& solid,
    const CellConnectivityCheck& reference, const std::vector<GraphEdge>& edges,
    const SectionScene& scene, const SectionArrangement& arrangement, const GridSpec& grid,
    const std::function<std::vector<std::uint8_t>(const GridSpec&)>& evaluate, int max_factor,
    std::int64_t max_voxels) {
  const std::vector<CuttingPlane>& planes = scene.planes;
  std::vector<CellRefinement> out;
  // The coarsest lattice (factor 2) has 2·(width + 4) + 1 points per axis: boxes wider than
  // max_voxels allows on all three axes are not searched to the end.
  const auto widest = std::int64_t(std::cbrt(double(max_voxels)) / 2);
  const auto pairsIn = [](const CellConnectivityCheck& c, int cell) {
    return cell >= 0 && std::size_t(cell) < c.pairs_by_cell.size() ? c.pairs_by_cell[std::size_t(cell)] : -1;
  };
  for (const int cell : cells) {
    CellRefinement r;
    r.cell = cell;
    r.pairs = pairsIn(solid, cell);
    r.reference_pairs = pairsIn(reference, cell);
    const std::vector<std::int8_t> signs = signsOfCell(cell, planes, arrangement);
    const auto box = signs.empty() ? std::nullopt : cellBox(cell, signs, planes, arrangement, grid, widest);
    for (int factor = 2; box && r.reference_pairs >= 0 && factor <= max_factor; factor *= 2) {
      // From two voxels below the box to two above, on the grid's centres and every 1/factor
      // between them.
      GridSpec fine;
      fine.voxel = grid.voxel / factor;
      fine.origin = grid.centre((*box)[0] - 2, (*box)[1] - 2, (*box)[2] - 2);
      for (int a = 0; a < 3; ++a)
        fine.dims[std::size_t(a)] = ((*box)[std::size_t(a + 3)] - (*box)[std::size_t(a)] + 4) * factor + 1;
      r.dims = fine.dims;
      if (fine.count() > max_voxels) break;
      const std::vector<std::uint8_t> inside = evaluate(fine);
      // The solid in the cell must stay inside the box: reaching its outer layer, it may join
      // sections through a part of the cell beyond it (not decided here: rejected).
      if (reachesOuterLayer(inside, fine, signs, planes)) {
        r.leaves_box = true;
        break;
      }
      const CellConnectivityCheck check =
          compareCellsWithVoxels(edges, scene, arrangement, inside, fine, {cell}, grid.voxel);
      const int pairs = pairsIn(check, cell);
      if (pairs < 0) continue;  // not resolved on this lattice: try a finer one
      r.factor = factor;
      r.refined_pairs = pairs;
      r.accepted = pairs <= r.reference_pairs;
      break;
    }
    out.push_back(r);
  }
  return out;
}

}  // namespace xsect
