// Ball closing and opening of a sparse voxel set, window by window (see block_ball_morphology.h).
#include "geometry/core/block_ball_morphology.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "geometry/core/ball_morphology.h"

namespace xsect {

namespace {

using Bytes = BlockGrid<std::uint8_t>;
constexpr int kSide = Bytes::kSide;

/// Radii under this are the voxel and its six face neighbours (ball_morphology.cpp).
constexpr double kCrossRadius = 1.4142135623730951;

enum class Operation { closing, opening };

Bytes windowed(const Bytes& set, double radius, Operation op) {
  if (!(radius > 0)) throw std::invalid_argument("ball morphology: the radius must be > 0 voxels");
  const GridSpec& g = set.grid();
  const int halo = radius < kCrossRadius ? 2 : int(std::ceil(2 * radius));
  // The cube's side: 4H (a window of (1.5 S)³, 3.4 times the cube's voxels) up to 96 voxels, so
  // that a window stays within 144³; at least 2H (a window of at most 8 times the cube's voxels)
  // for balls of more than 12 voxels.
  const int side = std::max(2 * halo, std::min(4 * halo, 96));
  const int m = std::max(1, (side + kSide - 1) / kSide);
  const int S = m * kSide;
  const std::array<int, 3>& nb = set.blockDims();
  const std::array<int, 3> cubes{(nb[0] + m - 1) / m, (nb[1] + m - 1) / m, (nb[2] + m - 1) / m};
  const std::int64_t cubeCount = std::int64_t(cubes[0]) * cubes[1] * cubes[2];
  Bytes out(g, 0);
  tbb::parallel_for(std::int64_t(0), cubeCount, [&](std::int64_t c) {
    const std::array<int, 3> cube{int(c % cubes[0]), int((c / cubes[0]) % cubes[1]),
                                  int(c / (std::int64_t(cubes[0]) * cubes[1]))};
    // The window's voxels [lo, hi), cut at the grid's faces (beyond them no voxel is in any of the
    // sets the transforms read, as for the dense grid), and its blocks [blo, bhi).
    std::array<int, 3> lo{}, hi{}, blo{}, bhi{};
    for (std::size_t a = 0; a < 3; ++a) {
      lo[a] = std::max(0, cube[a] * S - halo);
      hi[a] = std::min(g.dims[a], cube[a] * S + S + halo);
      blo[a] = lo[a] / kSide;
      bhi[a] = (hi[a] + kSide - 1) / kSide;
    }
    bool any = false, full = true;
    for (int bk = blo[2]; bk < bhi[2]; ++bk)
      for (int bj = blo[1]; bj < bhi[1]; ++bj)
        for (int bi = blo[0]; bi < bhi[0]; ++bi) {
          const std::int64_t b = set.block(bi, bj, bk);
          const bool leaf = set.isLeaf(b);
          any = any || leaf || set.tile(b);
          full = full && !leaf && set.tile(b);
        }
    const int cb0 = cube[0] * m, cb1 = cube[1] * m, cb2 = cube[2] * m;
    const auto eachBlock = [&](const auto& f) {
      for (int bk = cb2; bk < std::min(nb[2], cb2 + m); ++bk)
        for (int bj = cb1; bj < std::min(nb[1], cb1 + m); ++bj)
          for (int bi = cb0; bi < std::min(nb[0], cb0 + m); ++bi) f(out.block(bi, bj, bk));
    };
    if (!any) return;  // empty window: the cube stays empty in both
    if (full) {        // the window lies in the set: the cube is full in both
      eachBlock([&](std::int64_t b) { out.setTile(b, 1); });
      return;
    }
    GridSpec wg;
    wg.voxel = g.voxel;
    wg.dims = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    std::vector<std::uint8_t> window(std::size_t(wg.count()), 0);
    for (int k = lo[2]; k < hi[2]; ++k)
      for (int j = lo[1]; j < hi[1]; ++j)
        for (int i = lo[0]; i < hi[0]; ++i) window[std::size_t(wg.index(i - lo[0], j - lo[1], k - lo[2]))] = set.at(i, j, k);
    const BallMorphology morphology(window, wg, radius);
    const std::vector<std::uint8_t> result =
        op == Operation::closing ? morphology.closing(radius) : morphology.opening(radius);
    std::array<std::uint8_t, Bytes::kVoxels> values{};
    eachBlock([&](std::int64_t b) {
      const std::array<int, 3> o = out.blockOrigin(b);
      forEachVoxelOfBlock(g, o, [&](int i, int j, int k, int q) {
        values[std::size_t(q)] = result[std::size_t(wg.index(i - lo[0], j - lo[1], k - lo[2]))];
      });
      forEachBeyondGrid(g, o, [&](int q) { values[std::size_t(q)] = values[0]; });
      out.setBlock(b, values.data());
    });
  });
  return out;
}

}  // namespace

std::optional<VoxelBox> setBoundingBox(const Bytes& set) {
  VoxelBox box;
  const GridSpec& g = set.grid();
  box.lo = g.dims;
  for (std::int64_t b = 0; b < set.blockCount(); ++b) {
    if (!set.isLeaf(b) && !set.tile(b)) continue;
    forEachVoxelOfBlock(g, set.blockOrigin(b), [&](int i, int j, int k, int q) {
      if (set.isLeaf(b) && !set.leaf(b)[q]) return;
      const std::array<int, 3> v{i, j, k};
      for (std::size_t a = 0; a < 3; ++a) box.lo[a] = std::min(box.lo[a], v[a]), box.hi[a] = std::max(box.hi[a], v[a]);
    });
  }
  if (box.hi[0] < 0) return std::nullopt;
  return box;
}

Bytes paddedBlockGrid(const Bytes& set, int pad_blocks) {
  if (pad_blocks < 0) throw std::invalid_argument("paddedBlockGrid: negative padding");
  const int pad = pad_blocks * kSide;
  GridSpec g = set.grid();
  g.origin -= g.voxel * Vec3(pad, pad, pad);
  for (std::size_t a = 0; a < 3; ++a) g.dims[a] += 2 * pad;
  Bytes out(g, 0);
  const std::array<int, 3>& nb = set.blockDims();
  const GridSpec& from = set.grid();
  std::array<std::uint8_t, Bytes::kVoxels> values{};
  for (int bk = 0; bk < nb[2]; ++bk)
    for (int bj = 0; bj < nb[1]; ++bj)
      for (int bi = 0; bi < nb[0]; ++bi) {
        const std::int64_t b = set.block(bi, bj, bk), to = out.block(bi + pad_blocks, bj + pad_blocks, bk + pad_blocks);
        const std::array<int, 3> o = set.blockOrigin(b);
        const bool onUpperFace = o[0] + kSide > from.dims[0] || o[1] + kSide > from.dims[1] || o[2] + kSide > from.dims[2];
        if (!set.isLeaf(b) && (!onUpperFace || !set.tile(b))) {
          out.setTile(to, set.tile(b));
          continue;
        }
        // The old grid's upper faces now lie inside the new one: its voxels beyond them are outside.
        if (set.isLeaf(b)) std::copy(set.leaf(b), set.leaf(b) + Bytes::kVoxels, values.begin());
        else values.fill(1);
        forEachBeyondGrid(from, o, [&](int q) { values[std::size_t(q)] = 0; });
        out.setBlock(to, values.data());
      }
  return out;
}

Bytes blockBallClosing(const Bytes& set, double radius) { return windowed(set, radius, Operation::closing); }

Bytes blockBallOpening(const Bytes& set, double radius) { return windowed(set, radius, Operation::opening); }

}  // namespace xsect
