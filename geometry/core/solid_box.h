// The box of a voxel set with a margin of empty voxels, as a grid of its own: stages that need
// only the set (its Betti numbers, its morphology, its persistence) work on the set's box, not on
// the whole grid (topology_control.cpp, topology_confidence.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct SolidBox {
  GridSpec grid;                   ///< the box as a grid of its own (dims 0 when the set is empty)
  std::array<int, 3> lo{0, 0, 0};  ///< its first voxel on the whole grid
};

/// The bounding box of the voxels of `inside` (one byte per voxel of `g`) grown by `margin` voxels
/// on every side (it may reach beyond the grid).
inline SolidBox solidBox(const std::vector<std::uint8_t>& inside, const GridSpec& g, int margin) {
  std::array<int, 3> lo{g.dims[0], g.dims[1], g.dims[2]}, hi{-1, -1, -1};
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i)
        if (inside[std::size_t(g.index(i, j, k))]) {
          const std::array<int, 3> v{i, j, k};
          for (std::size_t a = 0; a < 3; ++a) lo[a] = std::min(lo[a], v[a]), hi[a] = std::max(hi[a], v[a]);
        }
  SolidBox b;
  b.grid.voxel = g.voxel;
  if (hi[0] < 0) return b;
  for (std::size_t a = 0; a < 3; ++a) {
    b.lo[a] = lo[a] - margin;
    b.grid.dims[a] = hi[a] - lo[a] + 1 + 2 * margin;
  }
  b.grid.origin = g.centre(b.lo[0], b.lo[1], b.lo[2]);
  return b;
}

/// `values` on the whole grid copied into the box (voxels beyond the grid: T{}).
template <typename T>
std::vector<T> intoBox(const std::vector<T>& values, const GridSpec& g, const SolidBox& b) {
  std::vector<T> out(std::size_t(b.grid.count()), T{});
  for (int k = 0; k < b.grid.dims[2]; ++k)
    for (int j = 0; j < b.grid.dims[1]; ++j)
      for (int i = 0; i < b.grid.dims[0]; ++i) {
        const int gi = i + b.lo[0], gj = j + b.lo[1], gk = k + b.lo[2];
        if (gi < 0 || gj < 0 || gk < 0 || gi >= g.dims[0] || gj >= g.dims[1] || gk >= g.dims[2]) continue;
        out[std::size_t(b.grid.index(i, j, k))] = values[std::size_t(g.index(gi, gj, gk))];
      }
  return out;
}

}  // namespace xsect
