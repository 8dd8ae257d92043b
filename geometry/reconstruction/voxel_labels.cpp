// Labels of the voxels of a reconstruction (see voxel_labels.h).
#include "geometry/reconstruction/voxel_labels.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <tuple>

#include "geometry/core/polygon.h"
#include "geometry/core/section_locator.h"

namespace xsect {

BlockGrid<std::uint16_t> voxelLabels(const BlockGrid<std::uint8_t>& inside, const BlockGrid<int>& section_plane,
                                     const std::vector<CuttingPlane>& planes,
                                     const std::vector<std::vector<Section>>& labelled,
                                     const std::vector<ObservedPiece>* pieces) {
  const GridSpec& grid = section_plane.grid();
  if (inside.grid().dims != grid.dims || inside.blockCount() != section_plane.blockCount())
    throw std::invalid_argument("voxel labels: the solid and the section planes lie on different grids");
  const auto& D = grid.dims;
  BlockGrid<std::uint16_t> label(grid, 0);
  // One point locator per plane (sectionContains' answer in section order, at the cost of the
  // edges near the point rather than the rings' length: on small grids the label pass was a
  // quarter of a run's time, a full ring scan per voxel of the solid).
  // `labelled` may end before the virtual end planes, which hold no section.
  const std::vector<Section> none;
  const auto sectionsOf = [&](std::size_t p) -> const std::vector<Section>& {
    return labelled.empty() ? planes[p].sections : p < labelled.size() ? labelled[p] : none;
  };
  std::vector<SectionLocator> locators(planes.size());
  tbb::parallel_for(std::size_t(0), planes.size(), [&](std::size_t p) {
    if (!sectionsOf(p).empty()) locators[p] = SectionLocator(sectionsOf(p));
  });
  // Per block of the solid: each voxel's label from its deciding plane; blocks without a voxel of
  // the solid stay tiles of 0. Voxels of a block beyond the grid repeat its first voxel.
  tbb::parallel_for(std::int64_t(0), inside.blockCount(), [&](std::int64_t b) {
    if (!inside.isLeaf(b) && !inside.tile(b)) return;
    const auto o = inside.blockOrigin(b);
    std::array<std::uint16_t, BlockGrid<std::uint16_t>::kVoxels> values;
    for (int dk = 0; dk < 8; ++dk)
      for (int dj = 0; dj < 8; ++dj)
        for (int di = 0; di < 8; ++di) {
          const int q = BlockGrid<std::uint16_t>::offset(di, dj, dk);
          values[std::size_t(q)] = 0;
          const int i = o[0] + di, j = o[1] + dj, k = o[2] + dk;
          if (i >= D[0] || j >= D[1] || k >= D[2]) {
            values[std::size_t(q)] = values[0];
            continue;
          }
          const int p = section_plane.at(i, j, k);
          if (!inside.at(i, j, k) || p < 0 || std::size_t(p) >= planes.size()) continue;
          Vec2 a = planes[std::size_t(p)].plane.toPlane(grid.centre(i, j, k));
          if (pieces) (*pieces)[std::size_t(p)].distance(a.x(), a.y(), &a.x(), &a.y());
          const int s = locators[std::size_t(p)].holding(a);
          if (s >= 0) values[std::size_t(q)] = std::uint16_t(sectionsOf(std::size_t(p))[std::size_t(s)].label);
        }
    label.setBlock(b, values.data());
  });
  // Unlabelled voxels of the solid: breadth-first from the labelled ones, taken in scan order
  // (rows of blocks without a voxel of the solid are skipped). Only labelled voxels beside an
  // unlabelled voxel of the solid start the search: the others would label nothing in its first
  // wave, so the labels are the same, and the front follows the unlabelled voxels, not the solid.
  const int nx = D[0], ny = D[1], nz = D[2];
  struct Voxel {
    int i, j, k;
  };
  const auto unlabelledAt = [&](int a, int b, int c) {
    return a >= 0 && b >= 0 && c >= 0 && a < nx && b < ny && c < nz && inside.at(a, b, c) && !label.at(a, b, c);
  };
  std::vector<Voxel> unlabelled;
  for (std::int64_t b = 0; b < inside.blockCount(); ++b) {
    if (!inside.isLeaf(b) && !inside.tile(b)) continue;
    const auto o = inside.blockOrigin(b);
    for (int k = o[2]; k < std::min(nz, o[2] + 8); ++k)
      for (int j = o[1]; j < std::min(ny, o[1] + 8); ++j)
        for (int i = o[0]; i < std::min(nx, o[0] + 8); ++i)
          if (unlabelledAt(i, j, k)) unlabelled.push_back({i, j, k});
  }
  if (unlabelled.empty()) return label;
  // The labelled neighbours of the unlabelled voxels, in scan order, once each.
  std::vector<Voxel> front, next;
  for (const Voxel& u : unlabelled)
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int a = u.i + dx, b = u.j + dy, c = u.k + dz;
          if (a < 0 || b < 0 || c < 0 || a >= nx || b >= ny || c >= nz) continue;
          if (label.at(a, b, c)) front.push_back({a, b, c});
        }
  const auto scanOrder = [](const Voxel& x, const Voxel& y) {
    return std::tie(x.k, x.j, x.i) < std::tie(y.k, y.j, y.i);
  };
  const auto same = [](const Voxel& x, const Voxel& y) { return x.i == y.i && x.j == y.j && x.k == y.k; };
  std::sort(front.begin(), front.end(), scanOrder);
  front.erase(std::unique(front.begin(), front.end(), same), front.end());
  while (!front.empty()) {
    next.clear();
    for (const Voxel& v : front) {
      const std::uint16_t l = label.at(v.i, v.j, v.k);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int a = v.i + dx, b = v.j + dy, c = v.k + dz;
            if (a < 0 || b < 0 || c < 0 || a >= nx || b >= ny || c >= nz) continue;
            if (inside.at(a, b, c) && !label.at(a, b, c)) {
              label.set(a, b, c, l);
              next.push_back({a, b, c});
            }
          }
    }
    front.swap(next);
  }
  label.compact();
  return label;
}

ScalarField labelField(const ScalarField& field, const std::vector<std::uint16_t>& labels,
                       std::uint16_t label, float nudge) {
  ScalarField f = field;
  for (std::size_t q = 0; q < f.values.size(); ++q) {
    float& v = f.values[q];
    if (labels[q] == label) v = std::min(v, -nudge);
    else if (labels[q] != 0) v = std::max(std::abs(v), nudge);
  }
  return f;
}

}  // namespace xsect
