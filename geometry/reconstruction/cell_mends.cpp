// The gaps closings fill and the necks openings cut, cell by cell (see cell_mends.h).
#include "geometry/reconstruction/cell_mends.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <unordered_map>

#include "geometry/core/ball_morphology.h"

namespace xsect {

bool planesAllow(const Vec3& x, bool value, const std::vector<CuttingPlane>& planes, std::size_t real_planes,
                 const std::vector<SectionDistanceField>& fields, double voxel) {
  for (std::size_t q = 0; q < real_planes && q < planes.size(); ++q) {
    const CuttingPlane& p = planes[q];
    if (!(std::abs(p.plane.signedDistance(x)) < voxel)) continue;
    const Vec2 at = p.plane.toPlane(x);
    if (!p.observed_everywhere && (!p.extent.contains(at) || !p.field_of_view.empty())) return false;
    const double d = fields[q].sample(at.x(), at.y());
    if (value ? !(d <= 0.5 * voxel) : !(d >= -0.5 * voxel)) return false;
  }
  return true;
}

namespace {

/// Calls f(w, i, j, k) for each of voxel v's 26 neighbours (and v itself) within the grid.
template <typename F>
void forEachNeighbour(std::int64_t v, const GridSpec& g, F f) {
  const std::array<int, 3> c = g.coordinates(v);
  for (int dk = -1; dk <= 1; ++dk)
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        const int i = c[0] + di, j = c[1] + dj, k = c[2] + dk;
        if (i < 0 || j < 0 || k < 0 || i >= g.dims[0] || j >= g.dims[1] || k >= g.dims[2]) continue;
        f(g.index(i, j, k), i, j, k);
      }
}

/// The voxels `changed` marks that the planes allow to change, grouped into 26-connected sets of one cell.
std::vector<CellMend> groupByCell(const std::vector<std::uint8_t>& changed, bool fill, double radius,
                                  const GridSpec& g, const std::vector<CuttingPlane>& planes,
                                  std::size_t realPlanes, const std::vector<SectionDistanceField>& fields,
                                  const SectionArrangement& arrangement) {
  std::unordered_map<std::int64_t, CellKey> keyOf;
  std::vector<std::int64_t> order;
  for (std::int64_t v = 0; v < g.count(); ++v) {
    if (!changed[std::size_t(v)]) continue;
    const std::array<int, 3> c = g.coordinates(v);
    const Vec3 x = g.centre(c[0], c[1], c[2]);
    if (!planesAllow(x, fill, planes, realPlanes, fields, g.voxel)) continue;
    keyOf.emplace(v, cellKeyAt(arrangement, planes, x));
    order.push_back(v);
  }
  std::unordered_map<std::int64_t, char> seen;
  std::vector<CellMend> mends;
  for (const std::int64_t seed : order) {
    if (seen.count(seed)) continue;
    CellMend m;
    m.fill = fill;
    m.radius = radius;
    m.key = keyOf.at(seed);
    std::vector<std::int64_t> queue{seed};
    seen[seed] = 1;
    for (std::size_t at = 0; at < queue.size(); ++at)
      forEachNeighbour(queue[at], g, [&](std::int64_t w, int, int, int) {
        const auto it = keyOf.find(w);
        if (it == keyOf.end() || it->second != m.key || seen.count(w)) return;
        seen[w] = 1;
        queue.push_back(w);
      });
    std::sort(queue.begin(), queue.end());
    m.voxels = std::move(queue);
    mends.push_back(std::move(m));
  }
  return mends;
}

/// The sections a mend touches (see CellMend::sections).
std::vector<int> touchedSections(const CellMend& m, const std::vector<std::uint8_t>& in,
                                 const std::vector<std::uint16_t>& src, const GridSpec& g,
                                 const std::vector<CuttingPlane>& planes, const SectionArrangement& arrangement) {
  std::set<int> sections;
  for (const std::int64_t v : m.voxels) {
    if (!m.fill) {
      if (src[std::size_t(v)]) sections.insert(src[std::size_t(v)]);
      continue;
    }
    forEachNeighbour(v, g, [&](std::int64_t w, int i, int j, int k) {
      if (!in[std::size_t(w)] || !src[std::size_t(w)] || sections.count(src[std::size_t(w)])) return;
      if (cellKeyAt(arrangement, planes, g.centre(i, j, k)) == m.key) sections.insert(src[std::size_t(w)]);
    });
  }
  return {sections.begin(), sections.end()};
}

}  // namespace

std::vector<CellMend> cellMends(const std::vector<std::uint8_t>& inside, const std::vector<std::uint16_t>& source,
                                const GridSpec& grid,
                                const std::vector<CuttingPlane>& planes, std::size_t real_planes,
                                const std::vector<SectionDistanceField>& fields,
                                const SectionArrangement& arrangement, int max_radius) {
  std::vector<CellMend> mends;
  std::set<std::pair<bool, std::vector<std::int64_t>>> found;
  const BallMorphology morphology(inside, grid, max_radius);  // every radius reads the same two distance transforms
  for (const bool fill : {true, false})
    for (int r = 1; r <= max_radius; ++r) {
      std::vector<std::uint8_t> changed = fill ? morphology.closing(r) : morphology.opening(r);
      for (std::size_t v = 0; v < changed.size(); ++v)
        changed[v] = fill ? changed[v] && !inside[v] : inside[v] && !changed[v];
      const double largestNeck = 4.0 * std::pow(2 * r + 1, 3);
      for (CellMend& m : groupByCell(changed, fill, r, grid, planes, real_planes, fields, arrangement)) {
        if (!fill && double(m.voxels.size()) > largestNeck) continue;
        if (!found.insert({fill, m.voxels}).second) continue;
        m.sections = touchedSections(m, inside, source, grid, planes, arrangement);
        mends.push_back(std::move(m));
      }
    }
  return mends;
}

}  // namespace xsect
