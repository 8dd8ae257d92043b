// Ball closing and opening of a voxel set (see ball_morphology.h).
#include "geometry/core/ball_morphology.h"

#include <stdexcept>

#include "geometry/core/distance_transform.h"

namespace xsect {

namespace {

/// The voxels within `radius` of the set (dilation by the ball).
std::vector<std::uint8_t> dilate(const std::vector<std::uint8_t>& set, const GridSpec& grid, double radius) {
  const std::vector<float> d = squaredDistanceToSet(set, grid, radius);
  std::vector<std::uint8_t> out(set.size());
  for (std::size_t v = 0; v < set.size(); ++v) out[v] = double(d[v]) <= radius * radius;
  return out;
}

std::vector<std::uint8_t> complement(std::vector<std::uint8_t> set) {
  for (std::uint8_t& v : set) v = !v;
  return set;
}

/// Radii under this are the voxel and its six face neighbours (the next voxel centres lie at sqrt(2)).
constexpr double kCrossRadius = 1.4142135623730951;

/// The dilation by the ball of radius 1 (the voxel and its face neighbours); voxels beyond the grid
/// are not in the set, as for the distance transform.
std::vector<std::uint8_t> dilateByCross(const std::vector<std::uint8_t>& set, const GridSpec& grid) {
  std::vector<std::uint8_t> out(set);
  const std::int64_t sx = 1, sy = grid.dims[0], sz = std::int64_t(grid.dims[0]) * grid.dims[1];
  for (int k = 0; k < grid.dims[2]; ++k)
    for (int j = 0; j < grid.dims[1]; ++j)
      for (int i = 0; i < grid.dims[0]; ++i) {
        const std::int64_t v = grid.index(i, j, k);
        if (!set[std::size_t(v)]) continue;
        if (i > 0) out[std::size_t(v - sx)] = 1;
        if (i + 1 < grid.dims[0]) out[std::size_t(v + sx)] = 1;
        if (j > 0) out[std::size_t(v - sy)] = 1;
        if (j + 1 < grid.dims[1]) out[std::size_t(v + sy)] = 1;
        if (k > 0) out[std::size_t(v - sz)] = 1;
        if (k + 1 < grid.dims[2]) out[std::size_t(v + sz)] = 1;
      }
  return out;
}

void requireRadius(double radius) {
  if (!(radius > 0)) throw std::invalid_argument("ball morphology: the radius must be > 0 voxels");
}

}  // namespace

std::vector<std::uint8_t> ballClosing(const std::vector<std::uint8_t>& set, const GridSpec& grid, double radius) {
  return BallMorphology(set, grid).closing(radius);
}

std::vector<std::uint8_t> ballOpening(const std::vector<std::uint8_t>& set, const GridSpec& grid, double radius) {
  return BallMorphology(set, grid).opening(radius);
}

BallMorphology::BallMorphology(const std::vector<std::uint8_t>& set, const GridSpec& grid, double max_radius)
    : set_(set), grid_(grid), max_radius_(max_radius) {}

const std::vector<float>& BallMorphology::toSet() const {
  std::call_once(set_once_, [&] { to_set_ = squaredDistanceToSet(set_, grid_, max_radius_); });
  return to_set_;
}

const std::vector<float>& BallMorphology::toComplement() const {
  std::call_once(complement_once_, [&] { to_complement_ = squaredDistanceToSet(complement(set_), grid_, max_radius_); });
  return to_complement_;
}

std::vector<std::uint8_t> BallMorphology::closing(double radius) const {
  requireRadius(radius);
  if (radius > max_radius_) throw std::invalid_argument("BallMorphology: a radius beyond the one it was made for");
  std::vector<std::uint8_t> out;
  if (radius < kCrossRadius) {  // the ball is the cross: no transform
    out = complement(dilateByCross(complement(dilateByCross(set_, grid_)), grid_));
  } else {
    // Erosion of the dilation = complement of the dilation of its complement.
    const std::vector<float>& d = toSet();
    std::vector<std::uint8_t> outside(set_.size());  // the complement of the dilation
    for (std::size_t v = 0; v < set_.size(); ++v) outside[v] = !(double(d[v]) <= radius * radius);
    out = complement(dilate(outside, grid_, radius));
  }
  for (std::size_t v = 0; v < set_.size(); ++v) out[v] |= set_[v];  // exact: the closing contains the set
  return out;
}

std::vector<std::uint8_t> BallMorphology::opening(double radius) const {
  requireRadius(radius);
  if (radius > max_radius_) throw std::invalid_argument("BallMorphology: a radius beyond the one it was made for");
  std::vector<std::uint8_t> out;
  if (radius < kCrossRadius) {
    out = dilateByCross(complement(dilateByCross(complement(set_), grid_)), grid_);
  } else {
    const std::vector<float>& d = toComplement();
    std::vector<std::uint8_t> eroded(set_.size());  // the complement of the complement's dilation
    for (std::size_t v = 0; v < set_.size(); ++v) eroded[v] = !(double(d[v]) <= radius * radius);
    out = dilate(eroded, grid_, radius);
  }
  for (std::size_t v = 0; v < set_.size(); ++v) out[v] &= set_[v];
  return out;
}

}  // namespace xsect
