// Evidence-based repair of a sampled solid and its Betti numbers (see digital_topology.h).
#include "geometry/core/digital_topology.h"

#include <array>

namespace xsect {

namespace {

using Index = std::int64_t;

/// Labels the components of voxels with value `v` (26- or 6-connectivity) and, per component,
/// whether it holds an anchor and whether it touches the grid border.
struct Components {
  std::vector<std::int32_t> label;  // -1 = not in the set
  std::vector<char> anchored, border;
};

Components components(const std::vector<std::uint8_t>& in, std::uint8_t v,
                      const std::vector<std::uint8_t>& anchor, const GridSpec& g, bool full26) {
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  Components c;
  c.label.assign(in.size(), -1);
  std::vector<std::array<int, 3>> offs;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int m = std::abs(dx) + std::abs(dy) + std::abs(dz);
        if (m == 0 || (!full26 && m > 1)) continue;
        offs.push_back({dx, dy, dz});
      }
  std::vector<Index> stack;
  for (Index s = 0; s < Index(in.size()); ++s) {
    if (in[s] != v || c.label[s] >= 0) continue;
    const std::int32_t id = std::int32_t(c.anchored.size());
    c.anchored.push_back(0);
    c.border.push_back(0);
    c.label[s] = id;
    stack.push_back(s);
    while (!stack.empty()) {
      const Index q = stack.back();
      stack.pop_back();
      if (anchor[q]) c.anchored[id] = 1;
      const int i = int(q % nx), j = int((q / nx) % ny), k = int(q / (Index(nx) * ny));
      if (i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1) c.border[id] = 1;
      for (const auto& o : offs) {
        const int a = i + o[0], b = j + o[1], d = k + o[2];
        if (a < 0 || b < 0 || d < 0 || a >= nx || b >= ny || d >= nz) continue;
        const Index r = g.index(a, b, d);
        if (in[r] == v && c.label[r] < 0) {
          c.label[r] = id;
          stack.push_back(r);
        }
      }
    }
  }
  return c;
}

/// One pass over all 2x2 squares and 2x2x2 cubes; adds a voxel to each critical configuration.
int removeCriticalConfigurations(std::vector<std::uint8_t>& in, const GridSpec& g) {
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  int added = 0;
  const Index sx = 1, sy = nx, sz = Index(nx) * ny;
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i) {
        const Index p = g.index(i, j, k);
        // 2x2 checkerboards in the three axis planes through p.
        const Index axes[3][2] = {{sx, sy}, {sx, sz}, {sy, sz}};
        for (const auto& ax : axes) {
          const Index a = p, b = p + ax[0], c = p + ax[1], d = p + ax[0] + ax[1];
          if (in[a] == in[d] && in[b] == in[c] && in[a] != in[b]) {
            in[in[a] ? b : a] = 1;
            ++added;
          }
        }
        // 2x2x2 cube: exactly two opposite corners differing from the other six.
        Index corner[8];
        int ones = 0;
        for (int q = 0; q < 8; ++q) {
          corner[q] = p + (q & 1 ? sx : 0) + (q & 2 ? sy : 0) + (q & 4 ? sz : 0);
          ones += in[corner[q]];
        }
        if (ones != 2 && ones != 6) continue;
        const std::uint8_t odd = ones == 2 ? 1 : 0;
        for (int q = 0; q < 4; ++q) {
          if (in[corner[q]] == odd && in[corner[7 - q]] == odd) {
            // vertex-critical pair q, 7-q: join (ones) or split (zeros) through an edge neighbour
            in[odd ? corner[q ^ 1] : corner[q]] = 1;
            ++added;
            break;
          }
        }
      }
  return added;
}

}  // namespace

int makeWellComposed(std::vector<std::uint8_t>& inside, const GridSpec& grid) {
  int added = 0;
  for (int a = removeCriticalConfigurations(inside, grid); a > 0; a = removeCriticalConfigurations(inside, grid))
    added += a;
  return added;
}

std::int64_t imposeSolid(ScalarField& field, const std::vector<std::uint8_t>& inside, float nudge_mm) {
  std::int64_t changed = 0;
  for (std::size_t q = 0; q < inside.size(); ++q) {
    float& v = field.values[q];
    if (inside[q] && !(v < 0)) {
      v = -nudge_mm;
      ++changed;
    } else if (!inside[q] && v < 0) {
      v = nudge_mm;
      ++changed;
    }
  }
  return changed;
}

TopologyRepair repairSampledTopology(std::vector<std::uint8_t>& inside,
                                     const std::vector<std::uint8_t>& inside_anchor,
                                     const std::vector<std::uint8_t>& outside_anchor,
                                     const GridSpec& grid) {
  TopologyRepair r;
  for (int round = 0; round < 8; ++round) {
    int changed = 0;
    {
      const Components fg = components(inside, 1, inside_anchor, grid, true);
      for (std::size_t q = 0; q < inside.size(); ++q)
        if (fg.label[q] >= 0 && !fg.anchored[fg.label[q]]) inside[q] = 0;
      for (std::size_t c = 0; c < fg.anchored.size(); ++c)
        if (!fg.anchored[c]) ++r.specks_removed, ++changed;
    }
    {
      const Components bg = components(inside, 0, outside_anchor, grid, false);
      for (std::size_t q = 0; q < inside.size(); ++q)
        if (bg.label[q] >= 0 && !bg.anchored[bg.label[q]] && !bg.border[bg.label[q]]) inside[q] = 1;
      for (std::size_t c = 0; c < bg.anchored.size(); ++c)
        if (!bg.anchored[c] && !bg.border[c]) ++r.cavities_filled, ++changed;
    }
    const int added = makeWellComposed(inside, grid);
    r.critical_voxels_added += added;
    if (changed == 0 && added == 0) break;
  }
  return r;
}

std::vector<int> solidComponents(const std::vector<std::uint8_t>& inside, const GridSpec& grid,
                                 int* count) {
  const std::vector<std::uint8_t> none(inside.size(), 0);
  Components fg = components(inside, 1, none, grid, true);
  *count = int(fg.anchored.size());
  return std::move(fg.label);
}

Betti voxelBetti(const std::vector<std::uint8_t>& in, const GridSpec& g) {
  const std::vector<std::uint8_t> none(in.size(), 0);
  const Components fg = components(in, 1, none, g, true);
  const Components bg = components(in, 0, none, g, false);
  int cavities = 0;
  for (char b : bg.border) cavities += !b;
  // Euler characteristic of the union of closed unit cubes centred on inside voxels.
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  const auto at = [&](int i, int j, int k) -> int {
    if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return 0;
    return in[g.index(i, j, k)];
  };
  long long V = 0, E = 0, F = 0, C = 0;
  // Lattice point (i, j, k) is the corner shared by voxels (i-1..i, j-1..j, k-1..k).
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        int v = 0;
        for (int q = 0; q < 8 && !v; ++q) v |= at(i - (q & 1), j - ((q >> 1) & 1), k - ((q >> 2) & 1));
        V += v;
        // edges from this lattice point along +x, +y, +z: each shared by 4 voxels
        int ex = 0, ey = 0, ez = 0;
        for (int q = 0; q < 4; ++q) {
          const int a = q & 1, b = (q >> 1) & 1;
          ex |= at(i, j - a, k - b);
          ey |= at(i - a, j, k - b);
          ez |= at(i - a, j - b, k);
        }
        E += ex + ey + ez;
        // faces with this lattice point as minimum corner, normal x / y / z: shared by 2 voxels
        F += (at(i, j, k) | at(i - 1, j, k)) + (at(i, j, k) | at(i, j - 1, k)) +
             (at(i, j, k) | at(i, j, k - 1));
        C += at(i, j, k);
      }
  const long long chi = V - E + F - C;
  const int b0 = int(fg.anchored.size());
  return {b0, int(b0 + cavities - chi), cavities};
}

}  // namespace xsect
