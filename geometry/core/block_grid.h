// Values on the voxels of a GridSpec, stored by blocks of 8³ voxels (issue 17): a block whose
// voxels all hold one value is a tile (that value, once); any other block is a leaf (its 512
// values). Memory follows the blocks where the values vary (for a reconstruction: the blocks the
// boundary passes through), not the grid's volume. The layout is OpenVDB's lowest level (8³
// leaves, tiles in their parent nodes), so a grid of these blocks converts to an OpenVDB tree leaf
// for leaf and tile for tile (meshing/volume_mesher.cpp), without OpenVDB's headers here.
//
// Blocks on the grid's upper faces may extend beyond the grid; their voxels outside it are never
// read and hold the block's tile value. Distinct blocks may be written from different threads.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// Blocks of 8³ voxels covering `grid` (BlockGrid's count, without building one).
inline std::int64_t blockCountOf(const GridSpec& grid) {
  std::int64_t n = 1;
  for (int a = 0; a < 3; ++a) n *= (std::int64_t(grid.dims[a]) + 7) / 8;
  return n;
}

template <typename T>
class BlockGrid {
 public:
  static constexpr int kSide = 8;                          ///< voxels per block edge
  static constexpr int kVoxels = kSide * kSide * kSide;    ///< voxels per block

  BlockGrid() = default;
  /// Every voxel of `grid` holds `fill` (one tile per block).
  BlockGrid(const GridSpec& grid, T fill) : grid_(grid) {
    for (int a = 0; a < 3; ++a) {
      if (grid.dims[a] < 0) throw std::invalid_argument("block grid: negative dimension");
      blocks_[a] = (grid.dims[a] + kSide - 1) / kSide;
    }
    const std::size_t n = std::size_t(blocks_[0]) * std::size_t(blocks_[1]) * std::size_t(blocks_[2]);
    tile_.assign(n, fill);
    leaf_.resize(n);
  }
  BlockGrid(const BlockGrid& o) : grid_(o.grid_), blocks_(o.blocks_), tile_(o.tile_), leaf_(o.leaf_.size()) {
    for (std::size_t b = 0; b < leaf_.size(); ++b)
      if (o.leaf_[b]) leaf_[b] = std::make_unique<Leaf>(*o.leaf_[b]);
  }
  BlockGrid(BlockGrid&&) noexcept = default;
  BlockGrid& operator=(BlockGrid o) noexcept {
    grid_ = o.grid_;
    blocks_ = o.blocks_;
    tile_.swap(o.tile_);
    leaf_.swap(o.leaf_);
    return *this;
  }

  const GridSpec& grid() const { return grid_; }
  /// Blocks along x, y, z.
  const std::array<int, 3>& blockDims() const { return blocks_; }
  std::int64_t blockCount() const { return std::int64_t(tile_.size()); }
  /// Block (bi, bj, bk) -> its index, x fastest.
  std::int64_t block(int bi, int bj, int bk) const {
    return (std::int64_t(bk) * blocks_[1] + bj) * blocks_[0] + bi;
  }
  /// First voxel (i, j, k) of block b.
  std::array<int, 3> blockOrigin(std::int64_t b) const {
    return {int(b % blocks_[0]) * kSide, int((b / blocks_[0]) % blocks_[1]) * kSide,
            int(b / (std::int64_t(blocks_[0]) * blocks_[1])) * kSide};
  }
  /// Place of voxel (i, j, k) inside its block, x fastest.
  static int offset(int i, int j, int k) { return (i & 7) + kSide * ((j & 7) + kSide * (k & 7)); }

  T at(int i, int j, int k) const {
    const std::size_t b = std::size_t(block(i >> 3, j >> 3, k >> 3));
    return leaf_[b] ? (*leaf_[b])[std::size_t(offset(i, j, k))] : tile_[b];
  }
  bool isLeaf(std::int64_t b) const { return bool(leaf_[std::size_t(b)]); }
  /// The tile value of block b (meaningful when it is not a leaf).
  T tile(std::int64_t b) const { return tile_[std::size_t(b)]; }
  /// The 512 values of a leaf, indexed by offset(); nullptr for a tile.
  const T* leaf(std::int64_t b) const { return leaf_[std::size_t(b)] ? leaf_[std::size_t(b)]->data() : nullptr; }

  /// Block b's values, by offset(): stored as a tile when they are all equal, as a leaf otherwise.
  void setBlock(std::int64_t b, const T* values) {
    bool uniform = true;
    for (int q = 1; q < kVoxels && uniform; ++q) uniform = values[q] == values[0];
    if (uniform) {
      setTile(b, values[0]);
      return;
    }
    auto& l = leaf_[std::size_t(b)];
    if (!l) l = std::make_unique<Leaf>();
    for (int q = 0; q < kVoxels; ++q) (*l)[std::size_t(q)] = values[q];
  }
  void setTile(std::int64_t b, T value) {
    tile_[std::size_t(b)] = value;
    leaf_[std::size_t(b)].reset();
  }
  /// Block b as a leaf (a tile is expanded into one), for voxel writes.
  T* leafForWriting(std::int64_t b) {
    auto& l = leaf_[std::size_t(b)];
    if (!l) {
      l = std::make_unique<Leaf>();
      l->fill(tile_[std::size_t(b)]);
    }
    return l->data();
  }
  void set(int i, int j, int k, T value) {
    leafForWriting(block(i >> 3, j >> 3, k >> 3))[offset(i, j, k)] = value;
  }

  /// Voxels (0 .. dims[0]-1, j, k) into out[0 .. dims[0]-1]: per block, 8 bytes copied from a
  /// leaf or filled from a tile.
  void readRow(int j, int k, T* out) const {
    const std::int64_t b0 = block(0, j >> 3, k >> 3);
    const int o = offset(0, j, k), nx = grid_.dims[0];
    for (int bi = 0; bi < blocks_[0]; ++bi) {
      const int n = std::min(kSide, nx - bi * kSide);
      const auto& l = leaf_[std::size_t(b0 + bi)];
      T* dst = out + bi * kSide;
      if (l) std::copy(l->data() + o, l->data() + o + n, dst);
      else std::fill(dst, dst + n, tile_[std::size_t(b0 + bi)]);
    }
  }
  /// Whether every block of the row of blocks (bj, bk) is a tile holding `value`.
  bool blockRowIs(int bj, int bk, T value) const {
    const std::int64_t b0 = block(0, bj, bk);
    for (int bi = 0; bi < blocks_[0]; ++bi)
      if (leaf_[std::size_t(b0 + bi)] || tile_[std::size_t(b0 + bi)] != value) return false;
    return true;
  }
  /// Leaves whose values are all equal become tiles again.
  void compact() {
    for (std::size_t b = 0; b < leaf_.size(); ++b) {
      if (!leaf_[b]) continue;
      const Leaf& l = *leaf_[b];
      if (std::all_of(l.begin(), l.end(), [&](T v) { return v == l[0]; })) {
        tile_[b] = l[0];
        leaf_[b].reset();
      }
    }
  }

  /// Number of voxels of the grid holding `value`.
  std::int64_t count(T value) const {
    std::int64_t n = 0;
    const auto& D = grid_.dims;
    for (std::int64_t b = 0; b < blockCount(); ++b) {
      const auto o = blockOrigin(b);
      const int ex = std::min(kSide, D[0] - o[0]), ey = std::min(kSide, D[1] - o[1]), ez = std::min(kSide, D[2] - o[2]);
      if (!leaf_[std::size_t(b)]) {
        if (tile_[std::size_t(b)] == value) n += std::int64_t(ex) * ey * ez;
        continue;
      }
      for (int k = 0; k < ez; ++k)
        for (int j = 0; j < ey; ++j)
          for (int i = 0; i < ex; ++i) n += (*leaf_[std::size_t(b)])[std::size_t(offset(i, j, k))] == value;
    }
    return n;
  }

  /// Number of leaves (blocks holding voxel values).
  std::int64_t leafCount() const {
    std::int64_t n = 0;
    for (const auto& l : leaf_) n += bool(l);
    return n;
  }

 private:
  using Leaf = std::array<T, std::size_t(kVoxels)>;
  GridSpec grid_;
  std::array<int, 3> blocks_{0, 0, 0};
  std::vector<T> tile_;
  std::vector<std::unique_ptr<Leaf>> leaf_;
};

/// Calls f(i, j, k, offset) for every voxel (i, j, k) of the block at `origin` (its first voxel)
/// that lies in `grid`, in scan order (x fastest).
template <typename F>
void forEachVoxelOfBlock(const GridSpec& grid, const std::array<int, 3>& origin, const F& f) {
  const auto& D = grid.dims;
  constexpr int n = BlockGrid<float>::kSide;
  for (int k = origin[2]; k < std::min(D[2], origin[2] + n); ++k)
    for (int j = origin[1]; j < std::min(D[1], origin[1] + n); ++j)
      for (int i = origin[0]; i < std::min(D[0], origin[0] + n); ++i) f(i, j, k, BlockGrid<float>::offset(i, j, k));
}

/// Calls f(offset) for every voxel of the block at `origin` (its first voxel) that lies beyond
/// `grid` (blocks on the grid's upper faces): the places a block's producer fills with a value of
/// the block so that a block uniform within the grid is a tile.
template <typename F>
void forEachBeyondGrid(const GridSpec& grid, const std::array<int, 3>& origin, const F& f) {
  const auto& D = grid.dims;
  constexpr int n = BlockGrid<float>::kSide;
  if (origin[0] + n <= D[0] && origin[1] + n <= D[1] && origin[2] + n <= D[2]) return;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        if (origin[0] + i >= D[0] || origin[1] + j >= D[1] || origin[2] + k >= D[2])
          f(BlockGrid<float>::offset(i, j, k));
}

/// The values of a block grid as a dense array (x fastest), for small grids and for the stages
/// that still read whole volumes.
template <typename T>
std::vector<T> denseValues(const BlockGrid<T>& g) {
  const auto& D = g.grid().dims;
  std::vector<T> values(std::size_t(g.grid().count()));
  for (int k = 0; k < D[2]; ++k)
    for (int j = 0; j < D[1]; ++j) g.readRow(j, k, values.data() + std::size_t(g.grid().index(0, j, k)));
  return values;
}

/// The inverse of denseValues: a dense array (x fastest) on `grid` stored by blocks, uniform blocks
/// as tiles (voxels beyond the grid repeat the block's first).
template <typename T>
BlockGrid<T> blockValues(const std::vector<T>& dense, const GridSpec& grid) {
  BlockGrid<T> g(grid, T{});
  std::array<T, BlockGrid<T>::kVoxels> values{};
  for (std::int64_t b = 0; b < g.blockCount(); ++b) {
    const auto o = g.blockOrigin(b);
    forEachVoxelOfBlock(grid, o, [&](int i, int j, int k, int q) { values[std::size_t(q)] = dense[std::size_t(grid.index(i, j, k))]; });
    forEachBeyondGrid(grid, o, [&](int q) { values[std::size_t(q)] = values[0]; });
    g.setBlock(b, values.data());
  }
  return g;
}

inline ScalarField denseField(const BlockGrid<float>& g) {
  ScalarField f;
  f.grid = g.grid();
  f.values = denseValues(g);
  return f;
}

}  // namespace xsect
