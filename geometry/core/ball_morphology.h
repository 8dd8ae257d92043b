// Closing and opening of a voxel set by a ball (the voxel centres within `radius` voxels of the
// centre), through the exact distance transform (distance_transform.h). The closing adds the gaps
// narrower than the ball (a slot of at most 2r voxels between two walls; not a hole through a thin
// sheet, which a ball can touch from outside); the opening removes the necks and fins thinner
// than it (at most 2r voxels across). Voxels beyond the grid count as outside the set, so a set
// should keep `radius` voxels of empty margin for the closing to mean the same as on a larger grid.
#pragma once

#include <cstdint>
#include <mutex>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// @param set     1 = voxel of the set, one byte per voxel of `grid`.
/// @param radius  the ball's radius, voxels (> 0).
/// @return        the closing (the set dilated by the ball, then eroded by it): a superset of `set`.
std::vector<std::uint8_t> ballClosing(const std::vector<std::uint8_t>& set, const GridSpec& grid, double radius);

/// @return        the opening (the set eroded by the ball, then dilated by it): a subset of `set`.
std::vector<std::uint8_t> ballOpening(const std::vector<std::uint8_t>& set, const GridSpec& grid, double radius);

/// Closings and openings of one set by several radii, sharing the distance transforms of the set
/// and of its complement (the dilations and erosions of every radius read them, computed once on
/// first need): six transforms for two radii instead of eight. A radius under sqrt(2) voxels is a
/// ball of the voxel and its six face neighbours, applied directly without a transform. Safe to
/// call from several threads at once.
class BallMorphology {
 public:
  /// @param max_radius  the largest radius asked for (voxels): the transforms need reach no farther.
  BallMorphology(const std::vector<std::uint8_t>& set, const GridSpec& grid, double max_radius = 1e30);
  std::vector<std::uint8_t> closing(double radius) const;  ///< ballClosing(set, grid, radius)
  std::vector<std::uint8_t> opening(double radius) const;  ///< ballOpening(set, grid, radius)

 private:
  const std::vector<float>& toSet() const;
  const std::vector<float>& toComplement() const;
  const std::vector<std::uint8_t>& set_;
  GridSpec grid_;
  double max_radius_;
  mutable std::once_flag set_once_, complement_once_;
  mutable std::vector<float> to_set_, to_complement_;  ///< squared distances, voxels²
};

}  // namespace xsect
