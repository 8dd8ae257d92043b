// Labels of the voxels of a reconstruction (see voxel_labels.h).
#include "geometry/reconstruction/voxel_labels.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <stdexcept>

#include "geometry/core/polygon.h"

namespace xsect {

std::vector<std::uint16_t> voxelLabels(const std::vector<std::uint8_t>& inside,
                                       const BlockGrid<int>& section_plane,
                                       const std::vector<CuttingPlane>& planes,
                                       const std::vector<std::vector<Section>>& labelled) {
  const GridSpec& grid = section_plane.grid();
  const std::size_t n = inside.size();
  if (std::int64_t(n) != grid.count()) throw std::invalid_argument("voxel labels: sizes differ");
  std::vector<std::uint16_t> label(n, 0);
  const int nx = grid.dims[0], ny = grid.dims[1];
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t q) {
    if (!inside[q]) return;
    const std::int64_t id = std::int64_t(q);
    const int i = int(id % nx), j = int((id / nx) % ny), k = int(id / (std::int64_t(nx) * ny));
    const int p = section_plane.at(i, j, k);
    if (p < 0 || std::size_t(p) >= planes.size()) return;
    const Vec3 x = grid.centre(i, j, k);
    const Vec2 a = planes[std::size_t(p)].plane.toPlane(x);
    for (const Section& s : labelled.empty() ? planes[std::size_t(p)].sections : labelled[std::size_t(p)])
      if (sectionContains(s, a)) {
        label[q] = std::uint16_t(s.label);
        return;
      }
  });
  // Unlabelled voxels of the solid: breadth-first from the labelled ones.
  std::vector<std::size_t> front, next;
  for (std::size_t q = 0; q < n; ++q)
    if (label[q]) front.push_back(q);
  while (!front.empty()) {
    next.clear();
    for (const std::size_t q : front) {
      const std::int64_t id = std::int64_t(q);
      const int i = int(id % nx), j = int((id / nx) % ny), k = int(id / (std::int64_t(nx) * ny));
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int a = i + dx, b = j + dy, c = k + dz;
            if (a < 0 || b < 0 || c < 0 || a >= nx || b >= ny || c >= grid.dims[2]) continue;
            const std::size_t r = std::size_t(grid.index(a, b, c));
            if (inside[r] && !label[r]) {
              label[r] = label[q];
              next.push_back(r);
            }
          }
    }
    front.swap(next);
  }
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
