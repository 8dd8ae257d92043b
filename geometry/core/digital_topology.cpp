// Evidence-based repair of a sampled solid and its Betti numbers (see digital_topology.h).
#include "geometry/core/digital_topology.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>

#include "geometry/core/disjoint_sets.h"

namespace xsect {

namespace {

using Index = std::int64_t;

/// The voxels of value `v` as runs along x, row by row (row r = j + ny k, rows in increasing r,
/// runs in increasing x): the components are found between runs, so that, past one sequential
/// read of the voxels, their cost and memory follow the number of runs (the set's boundary), not
/// of voxels: no label per voxel, no flood of the background (issue 17).
struct Runs {
  std::vector<std::int32_t> x0, x1;   // first and last voxel of each run
  std::vector<std::int64_t> first;    // per row: index of its first run; first[rows] = run count
};

Runs runsOf(const std::vector<std::uint8_t>& in, std::uint8_t v, const GridSpec& g) {
  const int nx = g.dims[0];
  const std::int64_t rows = std::int64_t(g.dims[1]) * g.dims[2];
  // Per slab of rows in parallel, then concatenated in order (deterministic).
  const std::int64_t slab = 256;
  const std::int64_t slabs = (rows + slab - 1) / slab;
  std::vector<Runs> parts(std::size_t(std::max<std::int64_t>(slabs, 0)));
  tbb::parallel_for(std::int64_t(0), slabs, [&](std::int64_t s) {
    Runs& p = parts[std::size_t(s)];
    for (std::int64_t r = s * slab; r < std::min(rows, (s + 1) * slab); ++r) {
      p.first.push_back(std::int64_t(p.x0.size()));
      const std::uint8_t* row = in.data() + r * nx;
      for (int i = 0; i < nx;) {
        if (row[i] != v) {
          ++i;
          continue;
        }
        int e = i;
        while (e + 1 < nx && row[e + 1] == v) ++e;
        p.x0.push_back(i);
        p.x1.push_back(e);
        i = e + 1;
      }
    }
  });
  Runs out;
  out.first.reserve(std::size_t(rows) + 1);
  for (const Runs& p : parts) {
    const std::int64_t offset = std::int64_t(out.x0.size());
    for (const std::int64_t f : p.first) out.first.push_back(offset + f);
    out.x0.insert(out.x0.end(), p.x0.begin(), p.x0.end());
    out.x1.insert(out.x1.end(), p.x1.begin(), p.x1.end());
  }
  out.first.push_back(std::int64_t(out.x0.size()));
  return out;
}

/// The components of voxels with value `v` (26- or 6-connectivity), numbered in the order of their
/// first voxel in scan order (the order a flood fill from each unlabelled voxel in turn gives),
/// per component whether it holds an anchor (an empty `anchor`: none does) and whether it touches
/// the grid border.
struct Components {
  Runs runs;
  std::vector<std::int32_t> of;  // component of each run
  std::vector<char> anchored, border;
  std::size_t count() const { return anchored.size(); }
};

Components components(const std::vector<std::uint8_t>& in, std::uint8_t v,
                      const std::vector<std::uint8_t>& anchor, const GridSpec& g, bool full26) {
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  Components c;
  c.runs = runsOf(in, v, g);
  const Runs& R = c.runs;
  const std::size_t n = R.x0.size();
  DisjointSets sets(n);
  // Each row against the rows before it that touch it: (j-1, k) and (j, k-1) for 6-connectivity;
  // also (j-1, k-1) and (j+1, k-1) for 26, where runs meet when they overlap once widened by one.
  const int grow = full26 ? 1 : 0;
  const auto join = [&](std::int64_t row, std::int64_t other) {
    std::int64_t a = R.first[std::size_t(row)], b = R.first[std::size_t(other)];
    const std::int64_t aEnd = R.first[std::size_t(row) + 1], bEnd = R.first[std::size_t(other) + 1];
    while (a < aEnd && b < bEnd) {
      if (R.x0[std::size_t(a)] - grow <= R.x1[std::size_t(b)] && R.x0[std::size_t(b)] <= R.x1[std::size_t(a)] + grow)
        sets.unite(std::size_t(a), std::size_t(b));
      // The one ending first meets nothing further on (a tie: the widened run, since the next
      // run of `other` starts at least two voxels on).
      if (R.x1[std::size_t(a)] + grow <= R.x1[std::size_t(b)]) ++a;
      else ++b;
    }
  };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      const std::int64_t row = j + std::int64_t(ny) * k;
      if (R.first[std::size_t(row)] == R.first[std::size_t(row) + 1]) continue;
      if (j > 0) join(row, row - 1);
      if (k > 0) {
        join(row, row - ny);
        if (full26) {
          if (j > 0) join(row, row - ny - 1);
          if (j + 1 < ny) join(row, row - ny + 1);
        }
      }
    }
  // Numbered by first run in scan order: a set's representative is its smallest run.
  c.of.assign(n, -1);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      const std::int64_t row = j + std::int64_t(ny) * k;
      const bool edgeRow = j == 0 || k == 0 || j == ny - 1 || k == nz - 1;
      for (std::int64_t r = R.first[std::size_t(row)]; r < R.first[std::size_t(row) + 1]; ++r) {
        const std::size_t root = sets.find(std::size_t(r));
        if (root == std::size_t(r)) {
          c.of[std::size_t(r)] = std::int32_t(c.anchored.size());
          c.anchored.push_back(0);
          c.border.push_back(0);
        } else {
          c.of[std::size_t(r)] = c.of[root];
        }
        const std::size_t id = std::size_t(c.of[std::size_t(r)]);
        const int x0 = R.x0[std::size_t(r)], x1 = R.x1[std::size_t(r)];
        if (edgeRow || x0 == 0 || x1 == nx - 1) c.border[id] = 1;
        if (!anchor.empty() && !c.anchored[id]) {
          const std::uint8_t* a = anchor.data() + row * nx;
          for (int i = x0; i <= x1; ++i)
            if (a[i]) {
              c.anchored[id] = 1;
              break;
            }
        }
      }
    }
  return c;
}

/// Sets every voxel of the runs of components `pick` chooses to `value`.
template <typename Pick>
void setComponents(std::vector<std::uint8_t>& in, const Components& c, int nx, const Pick& pick, std::uint8_t value) {
  const Runs& R = c.runs;
  const std::int64_t rows = std::int64_t(R.first.size()) - 1;
  for (std::int64_t row = 0; row < rows; ++row)
    for (std::int64_t r = R.first[std::size_t(row)]; r < R.first[std::size_t(row) + 1]; ++r)
      if (pick(std::size_t(c.of[std::size_t(r)])))
        std::fill(in.begin() + row * nx + R.x0[std::size_t(r)], in.begin() + row * nx + R.x1[std::size_t(r)] + 1, value);
}

/// Per row of voxels (j + ny k): whether it holds a voxel of the set.
std::vector<char> occupiedRows(const std::vector<std::uint8_t>& in, const GridSpec& g) {
  const int nx = g.dims[0];
  std::vector<char> rows(std::size_t(g.dims[1]) * std::size_t(g.dims[2]), 0);
  tbb::parallel_for(std::size_t(0), rows.size(), [&](std::size_t r) {
    const std::uint8_t* row = in.data() + r * std::size_t(nx);
    rows[r] = std::find(row, row + nx, std::uint8_t(1)) != row + nx;
  });
  return rows;
}

/// One pass over all 2x2 squares and 2x2x2 cubes; adds a voxel to each critical configuration.
/// Squares and cubes whose four rows of voxels hold none of the set hold no configuration and
/// are skipped (the rows' flags follow the voxels added, so the pass is the full pass).
int removeCriticalConfigurations(std::vector<std::uint8_t>& in, const GridSpec& g) {
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  int added = 0;
  const Index sx = 1, sy = nx, sz = Index(nx) * ny;
  std::vector<char> occupied = occupiedRows(in, g);
  const auto row = [&](int j, int k) { return std::size_t(j) + std::size_t(ny) * std::size_t(k); };
  const auto add = [&](Index x) {
    in[std::size_t(x)] = 1;
    occupied[std::size_t(x / nx)] = 1;
  };
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j) {
      if (!occupied[row(j, k)] && !occupied[row(j + 1, k)] && !occupied[row(j, k + 1)] && !occupied[row(j + 1, k + 1)])
        continue;
      for (int i = 0; i + 1 < nx; ++i) {
        const Index p = g.index(i, j, k);
        // 2x2 checkerboards in the three axis planes through p.
        const Index axes[3][2] = {{sx, sy}, {sx, sz}, {sy, sz}};
        for (const auto& ax : axes) {
          const Index a = p, b = p + ax[0], c = p + ax[1], d = p + ax[0] + ax[1];
          if (in[a] == in[d] && in[b] == in[c] && in[a] != in[b]) {
            add(in[a] ? b : a);
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
            add(odd ? corner[q ^ 1] : corner[q]);
            ++added;
            break;
          }
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

std::int64_t imposeSolid(BlockGrid<float>& field, const std::vector<std::uint8_t>& inside, float nudge_mm) {
  const GridSpec& g = field.grid();
  const auto& D = g.dims;
  std::vector<std::int64_t> changed(std::size_t(field.blockCount()), 0);
  tbb::parallel_for(std::int64_t(0), field.blockCount(), [&](std::int64_t b) {
    const auto o = field.blockOrigin(b);
    for (int k = o[2]; k < std::min(D[2], o[2] + 8); ++k)
      for (int j = o[1]; j < std::min(D[1], o[1] + 8); ++j)
        for (int i = o[0]; i < std::min(D[0], o[0] + 8); ++i) {
          const bool in = inside[std::size_t(g.index(i, j, k))];
          const float v = field.at(i, j, k);
          if (in == (v < 0)) continue;
          field.leafForWriting(b)[BlockGrid<float>::offset(i, j, k)] = in ? -nudge_mm : nudge_mm;
          ++changed[std::size_t(b)];
        }
  });
  std::int64_t n = 0;
  for (const std::int64_t c : changed) n += c;
  return n;
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
      setComponents(inside, fg, grid.dims[0], [&](std::size_t id) { return !fg.anchored[id]; }, 0);
      for (std::size_t c = 0; c < fg.count(); ++c)
        if (!fg.anchored[c]) ++r.specks_removed, ++changed;
    }
    {
      const Components bg = components(inside, 0, outside_anchor, grid, false);
      setComponents(inside, bg, grid.dims[0], [&](std::size_t id) { return !bg.anchored[id] && !bg.border[id]; }, 1);
      for (std::size_t c = 0; c < bg.count(); ++c)
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
  const Components fg = components(inside, 1, {}, grid, true);
  *count = int(fg.count());
  std::vector<int> label(inside.size(), -1);
  const Runs& R = fg.runs;
  const std::int64_t nx = grid.dims[0], rows = std::int64_t(R.first.size()) - 1;
  for (std::int64_t row = 0; row < rows; ++row)
    for (std::int64_t r = R.first[std::size_t(row)]; r < R.first[std::size_t(row) + 1]; ++r)
      std::fill(label.begin() + row * nx + R.x0[std::size_t(r)], label.begin() + row * nx + R.x1[std::size_t(r)] + 1,
                fg.of[std::size_t(r)]);
  return label;
}

Betti voxelBetti(const std::vector<std::uint8_t>& in, const GridSpec& g) {
  const Components fg = components(in, 1, {}, g, true);
  const Components bg = components(in, 0, {}, g, false);
  int cavities = 0;
  for (char b : bg.border) cavities += !b;
  // Euler characteristic of the union of closed unit cubes centred on inside voxels, summed per
  // layer of lattice points in parallel (integer sums: the same in any order); a row of lattice
  // points whose four neighbouring rows of voxels are empty adds nothing.
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  const std::vector<char> occupied = occupiedRows(in, g);
  const auto at = [&](int i, int j, int k) -> int {
    if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return 0;
    return in[g.index(i, j, k)];
  };
  const auto rowHas = [&](int j, int k) {
    return j >= 0 && k >= 0 && j < ny && k < nz && occupied[std::size_t(j) + std::size_t(ny) * std::size_t(k)];
  };
  std::vector<long long> layerChi(std::size_t(nz) + 1, 0);
  tbb::parallel_for(0, nz + 1, [&](int k) {
    long long V = 0, E = 0, F = 0, C = 0;
    // Lattice point (i, j, k) is the corner shared by voxels (i-1..i, j-1..j, k-1..k).
    for (int j = 0; j <= ny; ++j) {
      if (!rowHas(j, k) && !rowHas(j - 1, k) && !rowHas(j, k - 1) && !rowHas(j - 1, k - 1)) continue;
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
    }
    layerChi[std::size_t(k)] = V - E + F - C;
  });
  long long chiSum = 0;
  for (const long long x : layerChi) chiSum += x;
  const long long chi = chiSum;
  const int b0 = int(fg.count());
  return {b0, int(b0 + cavities - chi), cavities};
}

}  // namespace xsect
