// Ball closing and opening of a voxel set (see ball_morphology.h).
#include "geometry/core/ball_morphology.h"

#include <stdexcept>

#include "geometry/core/distance_transform.h"

namespace xsect {

namespace {

/// The voxels within `radius` of the set (dilation by the ball).
std::vector<std::uint8_t> dilate(const std::vector<std::uint8_t>& set, const GridSpec& grid, double radius) {
  const std::vector<float> d = squaredDistanceToSet(set, grid);
  std::vector<std::uint8_t> out(set.size());
  for (std::size_t v = 0; v < set.size(); ++v) out[v] = double(d[v]) <= radius * radius;
  return out;
}

std::vector<std::uint8_t> complement(std::vector<std::uint8_t> set) {
  for (std::uint8_t& v : set) v = !v;
  return set;
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

BallMorphology::BallMorphology(const std::vector<std::uint8_t>& set, const GridSpec& grid)
    : set_(set), grid_(grid), to_set_(squaredDistanceToSet(set, grid)), to_complement_(squaredDistanceToSet(complement(set), grid)) {}

std::vector<std::uint8_t> BallMorphology::closing(double radius) const {
  requireRadius(radius);
  // Erosion of the dilation = complement of the dilation of its complement.
  std::vector<std::uint8_t> outside(set_.size());  // the complement of the dilation
  for (std::size_t v = 0; v < set_.size(); ++v) outside[v] = !(double(to_set_[v]) <= radius * radius);
  std::vector<std::uint8_t> out = complement(dilate(outside, grid_, radius));
  for (std::size_t v = 0; v < set_.size(); ++v) out[v] |= set_[v];  // exact: the closing contains the set
  return out;
}

std::vector<std::uint8_t> BallMorphology::opening(double radius) const {
  requireRadius(radius);
  std::vector<std::uint8_t> eroded(set_.size());  // the complement of the complement's dilation
  for (std::size_t v = 0; v < set_.size(); ++v) eroded[v] = !(double(to_complement_[v]) <= radius * radius);
  std::vector<std::uint8_t> out = dilate(eroded, grid_, radius);
  for (std::size_t v = 0; v < set_.size(); ++v) out[v] &= set_[v];
  return out;
}

}  // namespace xsect
