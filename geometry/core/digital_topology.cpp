// Evidence-based repair of a sampled solid and its Betti numbers (see digital_topology.h).
#include "geometry/core/digital_topology.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>

#include "geometry/core/disjoint_sets.h"

namespace xsect {

namespace {

/// A voxel set read and written row by row (a row: the voxels (0 .. nx-1, j, k)), over its two
/// storages: dense bytes, or blocks of 8³ (block_grid.h). uniform(j, k) tells a row known to hold
/// one value throughout (0 or 1), -1 when it must be read; for dense bytes, rows without a voxel of
/// the set are known, for blocks the rows whose blocks are all tiles of one value. Writes keep it
/// true (a written row becomes unknown).
class DenseRows {
 public:
  /// Reads `in`; writes (fill) need `writable`, the same vector.
  DenseRows(const std::vector<std::uint8_t>& in, const GridSpec& g, std::vector<std::uint8_t>* writable = nullptr)
      : in_(&in), writable_(writable), nx_(g.dims[0]), ny_(g.dims[1]) {
    empty_.assign(std::size_t(g.dims[1]) * std::size_t(g.dims[2]), 0);
    tbb::parallel_for(std::size_t(0), empty_.size(), [&](std::size_t r) {
      const std::uint8_t* row = in.data() + r * std::size_t(nx_);
      empty_[r] = std::find(row, row + nx_, std::uint8_t(1)) == row + nx_;
    });
  }
  int uniform(int j, int k) const { return empty_[rowOf(j, k)] ? 0 : -1; }
  /// The value of every voxel of block column bi (x in 8 bi .. 8 bi + 7) of row (j, k) when known
  /// to be one value (never here), -1 otherwise.
  int uniformBlock(int, int, int) const { return -1; }
  const std::uint8_t* row(int j, int k, std::uint8_t*) const { return in_->data() + rowOf(j, k) * std::size_t(nx_); }
  void fill(int j, int k, int x0, int x1, std::uint8_t v) {
    std::uint8_t* r = writable_->data() + rowOf(j, k) * std::size_t(nx_);
    std::fill(r + x0, r + x1 + 1, v);
    if (v) empty_[rowOf(j, k)] = 0;
  }
  void finish() {}

 private:
  std::size_t rowOf(int j, int k) const { return std::size_t(j) + std::size_t(ny_) * std::size_t(k); }
  const std::vector<std::uint8_t>* in_;
  std::vector<std::uint8_t>* writable_;
  int nx_, ny_;
  std::vector<char> empty_;
};

class BlockRows {
 public:
  using Grid = BlockGrid<std::uint8_t>;
  /// Reads `in`; writes (fill) need `writable`, the same grid.
  explicit BlockRows(const Grid& in, Grid* writable = nullptr) : in_(&in), writable_(writable) {
    const auto& B = in.blockDims();
    uniform_.assign(std::size_t(B[1]) * std::size_t(B[2]), -1);
    tbb::parallel_for(std::size_t(0), uniform_.size(), [&](std::size_t r) {
      const int bj = int(r % std::size_t(B[1])), bk = int(r / std::size_t(B[1]));
      uniform_[r] = in.blockRowIs(bj, bk, 0) ? 0 : in.blockRowIs(bj, bk, 1) ? 1 : -1;
    });
  }
  int uniform(int j, int k) const { return uniform_[rowOf(j, k)]; }
  /// The tile value of the block holding voxels (8 bi .. 8 bi + 7, j, k), -1 for a leaf.
  int uniformBlock(int bi, int j, int k) const {
    const std::int64_t b = in_->block(bi, j >> 3, k >> 3);
    return in_->isLeaf(b) ? -1 : int(in_->tile(b));
  }
  const std::uint8_t* row(int j, int k, std::uint8_t* scratch) const {
    in_->readRow(j, k, scratch);
    return scratch;
  }
  void fill(int j, int k, int x0, int x1, std::uint8_t v) {
    for (int i = x0; i <= x1; ++i) writable_->set(i, j, k, v);
    uniform_[rowOf(j, k)] = -1;
  }
  /// Leaves that became uniform are tiles again.
  void finish() {
    if (writable_) writable_->compact();
  }

 private:
  std::size_t rowOf(int j, int k) const { return std::size_t(j >> 3) + std::size_t(in_->blockDims()[1]) * std::size_t(k >> 3); }
  const Grid* in_;
  Grid* writable_;
  std::vector<signed char> uniform_;
};

/// The voxels of value `v` as runs along x, row by row (row r = j + ny k, rows in increasing r,
/// runs in increasing x): the components are found between runs, so that, past one sequential
/// read of the voxels, their cost and memory follow the number of runs (the set's boundary), not
/// of voxels: no label per voxel, no flood of the background (issue 17).
struct Runs {
  std::vector<std::int32_t> x0, x1;   // first and last voxel of each run
  std::vector<std::int64_t> first;    // per row: index of its first run; first[rows] = run count
};

template <typename Rows>
Runs runsOf(const Rows& in, std::uint8_t v, const GridSpec& g) {
  const int nx = g.dims[0], ny = g.dims[1];
  const std::int64_t rows = std::int64_t(g.dims[1]) * g.dims[2];
  // Per slab of rows in parallel, then concatenated in order (deterministic).
  const std::int64_t slab = 256;
  const std::int64_t slabs = (rows + slab - 1) / slab;
  std::vector<Runs> parts(std::size_t(std::max<std::int64_t>(slabs, 0)));
  tbb::parallel_for(std::int64_t(0), slabs, [&](std::int64_t s) {
    Runs& p = parts[std::size_t(s)];
    std::vector<std::uint8_t> scratch(std::size_t(nx) + 8);
    for (std::int64_t r = s * slab; r < std::min(rows, (s + 1) * slab); ++r) {
      p.first.push_back(std::int64_t(p.x0.size()));
      const int j = int(r % ny), k = int(r / ny);
      const int u = in.uniform(j, k);
      if (u >= 0) {  // one value throughout: one run or none
        if (u == v && nx > 0) {
          p.x0.push_back(0);
          p.x1.push_back(nx - 1);
        }
        continue;
      }
      const std::uint8_t* row = in.row(j, k, scratch.data());
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

template <typename Rows>
Components components(const Rows& in, std::uint8_t v, const Rows* anchor, const GridSpec& g, bool full26) {
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
  std::vector<std::uint8_t> scratch(std::size_t(nx) + 8);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      const std::int64_t row = j + std::int64_t(ny) * k;
      const bool edgeRow = j == 0 || k == 0 || j == ny - 1 || k == nz - 1;
      const std::uint8_t* a = nullptr;  // the anchors' row, read when a run needs it
      const int anchorRow = anchor ? anchor->uniform(j, k) : 0;
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
        if (anchorRow == 1) c.anchored[id] = 1;
        if (anchorRow < 0 && !c.anchored[id]) {
          if (!a) a = anchor->row(j, k, scratch.data());
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
template <typename Rows, typename Pick>
void setComponents(Rows& in, const Components& c, int ny, const Pick& pick, std::uint8_t value) {
  const Runs& R = c.runs;
  const std::int64_t rows = std::int64_t(R.first.size()) - 1;
  for (std::int64_t row = 0; row < rows; ++row)
    for (std::int64_t r = R.first[std::size_t(row)]; r < R.first[std::size_t(row) + 1]; ++r)
      if (pick(std::size_t(c.of[std::size_t(r)])))
        in.fill(int(row % ny), int(row / ny), R.x0[std::size_t(r)], R.x1[std::size_t(r)], value);
}

/// One pass over all 2x2 squares and 2x2x2 cubes, in scan order; adds a voxel to each critical
/// configuration. Squares and cubes whose voxels are known to hold one value hold no
/// configuration and are skipped: whole quads of rows known uniform, and, within a quad, the cubes
/// inside blocks known uniform (tiles); the flags follow the voxels added, so the pass is the full
/// pass (the same voxels added in the same order), at the cost of the blocks the boundary crosses.
template <typename Rows>
int removeCriticalConfigurations(Rows& in, const GridSpec& g) {
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  const int nbx = (nx + 7) / 8;
  int added = 0;
  // Rows 0 .. 3 of a quad: (j, k), (j+1, k), (j, k+1), (j+1, k+1); corner q of a cube at column i
  // is voxel i + (q & 1) of row q >> 1.
  std::array<std::vector<std::uint8_t>, 4> row;
  for (auto& r : row) r.assign(std::size_t(nx) + 8, 0);
  std::vector<std::uint8_t> scratch(std::size_t(nx) + 8);
  std::vector<int> block(std::size_t(nbx) + 1, -1);  // per block column: the quad's one value, or -1
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j) {
      const int u[4] = {in.uniform(j, k), in.uniform(j + 1, k), in.uniform(j, k + 1), in.uniform(j + 1, k + 1)};
      if (u[0] >= 0 && u[0] == u[1] && u[0] == u[2] && u[0] == u[3]) continue;
      for (int bi = 0; bi < nbx; ++bi) {
        const int v = in.uniformBlock(bi, j, k);
        const bool same = v >= 0 && in.uniformBlock(bi, j + 1, k) == v && in.uniformBlock(bi, j, k + 1) == v &&
                          in.uniformBlock(bi, j + 1, k + 1) == v;
        block[std::size_t(bi)] = same ? v : -1;
      }
      for (int r = 0; r < 4; ++r) {
        const std::uint8_t* src = in.row(j + (r & 1), k + (r >> 1), scratch.data());
        std::copy(src, src + nx, row[std::size_t(r)].begin());
      }
      const auto add = [&](int i, int q) {
        const int r = q >> 1, x = i + (q & 1);
        row[std::size_t(r)][std::size_t(x)] = 1;
        in.fill(j + (r & 1), k + (r >> 1), x, x, 1);
        block[std::size_t(x >> 3)] = -1;
      };
      for (int i = 0; i + 1 < nx; ++i) {
        const int b0 = block[std::size_t(i >> 3)];
        if (b0 >= 0 && b0 == block[std::size_t((i + 1) >> 3)]) continue;  // one value throughout
        std::uint8_t c[8];
        for (int q = 0; q < 8; ++q) c[q] = row[std::size_t(q >> 1)][std::size_t(i + (q & 1))];
        // 2x2 checkerboards in the three axis planes through corner 0 (xy, xz, yz).
        const int axes[3][2] = {{1, 2}, {1, 4}, {2, 4}};
        for (const auto& ax : axes) {
          const int a = 0, b = ax[0], e = ax[1], d = ax[0] + ax[1];
          if (c[a] == c[d] && c[b] == c[e] && c[a] != c[b]) {
            const int q = c[a] ? b : a;
            add(i, q);
            c[q] = 1;
            ++added;
          }
        }
        // 2x2x2 cube: exactly two opposite corners differing from the other six.
        int ones = 0;
        for (int q = 0; q < 8; ++q) ones += c[q];
        if (ones != 2 && ones != 6) continue;
        const std::uint8_t odd = ones == 2 ? 1 : 0;
        for (int q = 0; q < 4; ++q) {
          if (c[q] == odd && c[7 - q] == odd) {
            // vertex-critical pair q, 7-q: join (ones) or split (zeros) through an edge neighbour
            add(i, odd ? q ^ 1 : q);
            ++added;
            break;
          }
        }
      }
    }
  return added;
}

template <typename Rows>
int wellComposed(Rows& rows, const GridSpec& grid) {
  int added = 0;
  for (int a = removeCriticalConfigurations(rows, grid); a > 0; a = removeCriticalConfigurations(rows, grid))
    added += a;
  rows.finish();
  return added;
}

template <typename Rows>
TopologyRepair repair(Rows& inside, const Rows& inside_anchor, const Rows& outside_anchor, const GridSpec& grid) {
  TopologyRepair r;
  for (int round = 0; round < 8; ++round) {
    int changed = 0;
    {
      const Components fg = components(inside, 1, &inside_anchor, grid, true);
      setComponents(inside, fg, grid.dims[1], [&](std::size_t id) { return !fg.anchored[id]; }, 0);
      for (std::size_t c = 0; c < fg.count(); ++c)
        if (!fg.anchored[c]) ++r.specks_removed, ++changed;
    }
    {
      const Components bg = components(inside, 0, &outside_anchor, grid, false);
      setComponents(inside, bg, grid.dims[1], [&](std::size_t id) { return !bg.anchored[id] && !bg.border[id]; }, 1);
      for (std::size_t c = 0; c < bg.count(); ++c)
        if (!bg.anchored[c] && !bg.border[c]) ++r.cavities_filled, ++changed;
    }
    const int added = wellComposed(inside, grid);
    r.critical_voxels_added += added;
    if (changed == 0 && added == 0) break;
  }
  inside.finish();
  return r;
}

template <typename Rows>
Betti betti(const Rows& in, const GridSpec& g) {
  const Components fg = components(in, 1, static_cast<const Rows*>(nullptr), g, true);
  const Components bg = components(in, 0, static_cast<const Rows*>(nullptr), g, false);
  int cavities = 0;
  for (char b : bg.border) cavities += !b;
  // Euler characteristic of the union of closed unit cubes centred on inside voxels, summed per
  // layer of lattice points in parallel (integer sums: the same in any order); a row of lattice
  // points whose four neighbouring rows of voxels are empty adds nothing.
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  const auto empty = [&](int j, int k) { return j < 0 || k < 0 || j >= ny || k >= nz || in.uniform(j, k) == 0; };
  std::vector<long long> layerChi(std::size_t(nz) + 1, 0);
  tbb::parallel_for(0, nz + 1, [&](int k) {
    long long V = 0, E = 0, F = 0, C = 0;
    // R[b][c]: voxel row (j - b, k - c), padded with a zero on each side (index -1 and nx).
    std::array<std::array<std::vector<std::uint8_t>, 2>, 2> buffer;
    for (auto& a : buffer)
      for (auto& b : a) b.assign(std::size_t(nx) + 2, 0);
    std::vector<std::uint8_t> scratch(std::size_t(nx) + 8);
    const std::uint8_t* R[2][2];
    // Lattice point (i, j, k) is the corner shared by voxels (i-1..i, j-1..j, k-1..k).
    for (int j = 0; j <= ny; ++j) {
      if (empty(j, k) && empty(j - 1, k) && empty(j, k - 1) && empty(j - 1, k - 1)) continue;
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c) {
          std::vector<std::uint8_t>& buf = buffer[std::size_t(b)][std::size_t(c)];
          if (empty(j - b, k - c)) {
            std::fill(buf.begin(), buf.end(), std::uint8_t(0));
          } else {
            const std::uint8_t* src = in.row(j - b, k - c, scratch.data());
            std::copy(src, src + nx, buf.begin() + 1);
          }
          R[b][c] = buf.data() + 1;
        }
      for (int i = 0; i <= nx; ++i) {
        int v = 0;
        for (int q = 0; q < 8 && !v; ++q) v |= R[(q >> 1) & 1][(q >> 2) & 1][i - (q & 1)];
        V += v;
        // edges from this lattice point along +x, +y, +z: each shared by 4 voxels
        int ex = 0, ey = 0, ez = 0;
        for (int q = 0; q < 4; ++q) {
          const int a = q & 1, b = (q >> 1) & 1;
          ex |= R[a][b][i];
          ey |= R[0][b][i - a];
          ez |= R[b][0][i - a];
        }
        E += ex + ey + ez;
        // faces with this lattice point as minimum corner, normal x / y / z: shared by 2 voxels
        const int own = R[0][0][i];
        F += (own | R[0][0][i - 1]) + (own | R[1][0][i]) + (own | R[0][1][i]);
        C += own;
      }
    }
    layerChi[std::size_t(k)] = V - E + F - C;
  });
  long long chi = 0;
  for (const long long x : layerChi) chi += x;
  const int b0 = int(fg.count());
  return {b0, int(b0 + cavities - chi), cavities};
}

}  // namespace

int makeWellComposed(std::vector<std::uint8_t>& inside, const GridSpec& grid) {
  DenseRows rows(inside, grid, &inside);
  return wellComposed(rows, grid);
}

int makeWellComposed(BlockGrid<std::uint8_t>& inside) {
  BlockRows rows(inside, &inside);
  return wellComposed(rows, inside.grid());
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

std::int64_t imposeSolid(BlockGrid<float>& field, const BlockGrid<std::uint8_t>& inside, float nudge_mm) {
  const GridSpec& g = field.grid();
  std::vector<std::int64_t> changed(std::size_t(field.blockCount()), 0);
  tbb::parallel_for(std::int64_t(0), field.blockCount(), [&](std::int64_t b) {
    // Two tiles that agree: nothing to change.
    if (!field.isLeaf(b) && !inside.isLeaf(b) && (field.tile(b) < 0) == bool(inside.tile(b))) return;
    forEachVoxelOfBlock(g, field.blockOrigin(b), [&](int i, int j, int k, int o) {
      const bool in = inside.at(i, j, k);
      const float v = field.at(i, j, k);
      if (in == (v < 0)) return;
      field.leafForWriting(b)[o] = in ? -nudge_mm : nudge_mm;
      ++changed[std::size_t(b)];
    });
  });
  std::int64_t n = 0;
  for (const std::int64_t c : changed) n += c;
  return n;
}

TopologyRepair repairSampledTopology(std::vector<std::uint8_t>& inside,
                                     const std::vector<std::uint8_t>& inside_anchor,
                                     const std::vector<std::uint8_t>& outside_anchor,
                                     const GridSpec& grid) {
  DenseRows rows(inside, grid, &inside);
  const DenseRows in(inside_anchor, grid), out(outside_anchor, grid);
  return repair(rows, in, out, grid);
}

TopologyRepair repairSampledTopology(BlockGrid<std::uint8_t>& inside, const BlockGrid<std::uint8_t>& inside_anchor,
                                     const BlockGrid<std::uint8_t>& outside_anchor) {
  BlockRows rows(inside, &inside);
  const BlockRows in(inside_anchor), out(outside_anchor);
  return repair(rows, in, out, inside.grid());
}

namespace {

template <typename Rows>
SolidComponentIndex componentIndex(const Rows& rows, const GridSpec& grid) {
  Components fg = components(rows, 1, static_cast<const Rows*>(nullptr), grid, true);
  SolidComponentIndex index;
  index.grid = grid;
  index.count = int(fg.count());
  index.x0 = std::move(fg.runs.x0);
  index.x1 = std::move(fg.runs.x1);
  index.first = std::move(fg.runs.first);
  index.component = std::move(fg.of);
  return index;
}

}  // namespace

int SolidComponentIndex::at(int i, int j, int k) const {
  const std::size_t row = std::size_t(j) + std::size_t(grid.dims[1]) * std::size_t(k);
  const auto begin = x1.begin() + first[row], end = x1.begin() + first[row + 1];
  const auto it = std::lower_bound(begin, end, i);  // the first run ending at or after i
  if (it == end || x0[std::size_t(it - x1.begin())] > i) return -1;
  return component[std::size_t(it - x1.begin())];
}

SolidComponentIndex solidComponentIndex(const std::vector<std::uint8_t>& inside, const GridSpec& grid) {
  return componentIndex(DenseRows(inside, grid), grid);
}

SolidComponentIndex solidComponentIndex(const BlockGrid<std::uint8_t>& inside) {
  return componentIndex(BlockRows(inside), inside.grid());
}

std::vector<int> solidComponents(const std::vector<std::uint8_t>& inside, const GridSpec& grid,
                                 int* count) {
  const SolidComponentIndex index = solidComponentIndex(inside, grid);
  *count = index.count;
  std::vector<int> label(inside.size(), -1);
  const std::int64_t nx = grid.dims[0], rows = std::int64_t(index.first.size()) - 1;
  for (std::int64_t row = 0; row < rows; ++row)
    for (std::int64_t r = index.first[std::size_t(row)]; r < index.first[std::size_t(row) + 1]; ++r)
      std::fill(label.begin() + row * nx + index.x0[std::size_t(r)], label.begin() + row * nx + index.x1[std::size_t(r)] + 1,
                index.component[std::size_t(r)]);
  return label;
}

Betti voxelBetti(const std::vector<std::uint8_t>& in, const GridSpec& g) {
  return betti(DenseRows(in, g), g);
}

Betti voxelBetti(const BlockGrid<std::uint8_t>& in) {
  return betti(BlockRows(in), in.grid());
}

long long eulerCharacteristicChange(const std::vector<std::uint8_t>& in, const GridSpec& g,
                                    const std::vector<std::int64_t>& voxels, std::uint8_t value) {
  if (voxels.empty()) return 0;
  std::array<int, 3> lo{g.dims[0], g.dims[1], g.dims[2]}, hi{-1, -1, -1};
  for (const std::int64_t v : voxels) {
    const std::array<int, 3> c = g.coordinates(v);
    for (std::size_t a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
  }
  // Voxel (i, j, k) is the cube of doubled coordinates [2i, 2i + 2]^3; a lattice cell of doubled
  // coordinates (a, b, c) has dimension the number of odd ones, and lies in the union when one of
  // the voxels it bounds (one per odd coordinate, two per even one) is in the set.
  const auto member = [&](int i, int j, int k, bool after) -> int {
    if (i < 0 || j < 0 || k < 0 || i >= g.dims[0] || j >= g.dims[1] || k >= g.dims[2]) return 0;
    const std::int64_t v = g.index(i, j, k);
    if (after && std::binary_search(voxels.begin(), voxels.end(), v)) return value ? 1 : 0;
    return in[std::size_t(v)] ? 1 : 0;
  };
  long long change = 0;
  for (int c = 2 * lo[2]; c <= 2 * hi[2] + 2; ++c)
    for (int b = 2 * lo[1]; b <= 2 * hi[1] + 2; ++b)
      for (int a = 2 * lo[0]; a <= 2 * hi[0] + 2; ++a) {
        const std::array<int, 3> d{a, b, c};
        std::array<int, 3> first{}, count{};
        int dim = 0;
        for (std::size_t x = 0; x < 3; ++x) {
          const bool odd = d[x] & 1;
          dim += odd;
          first[x] = odd ? (d[x] - 1) / 2 : d[x] / 2 - 1;
          count[x] = odd ? 1 : 2;
        }
        int before = 0, after = 0;
        for (int z = 0; z < count[2]; ++z)
          for (int y = 0; y < count[1]; ++y)
            for (int x = 0; x < count[0]; ++x) {
              before |= member(first[0] + x, first[1] + y, first[2] + z, false);
              after |= member(first[0] + x, first[1] + y, first[2] + z, true);
            }
        change += (dim % 2 ? -1 : 1) * (after - before);
      }
  return change;
}

}  // namespace xsect
