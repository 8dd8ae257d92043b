// Persistence of a voxel solid's handles and cavities (see topology_features.h). GUDHI's headers
// stay in this translation unit.
#include "geometry/reconstruction/topology_features.h"

#include <gudhi/Bitmap_cubical_complex.h>
#include <gudhi/Persistent_cohomology.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>

#include "geometry/core/distance_transform.h"

namespace xsect {

namespace {

using CubicalBase = Gudhi::cubical_complex::Bitmap_cubical_complex_base<double>;
using Cubical = Gudhi::cubical_complex::Bitmap_cubical_complex<CubicalBase>;
using Cohomology = Gudhi::persistent_cohomology::Persistent_cohomology<Cubical, Gudhi::persistent_cohomology::Field_Zp>;

/// The signed distance of each voxel's centre to the solid's boundary, in voxels, offset by half
/// a voxel so that the voxels of the solid are exactly those <= 0: minus the distance to the
/// nearest voxel outside, less a half, inside; the distance to the nearest voxel inside, less a
/// half, outside.
std::vector<double> signedDistance(const std::vector<std::uint8_t>& inside, const GridSpec& g) {
  std::vector<std::uint8_t> outside(inside.size());
  for (std::size_t v = 0; v < inside.size(); ++v) outside[v] = !inside[v];
  const std::vector<float> toOutside = squaredDistanceToSet(outside, g);
  const std::vector<float> toInside = squaredDistanceToSet(inside, g);
  std::vector<double> f(inside.size());
  for (std::size_t v = 0; v < inside.size(); ++v)
    f[v] = inside[v] ? -(std::sqrt(double(toOutside[v])) - 0.5) : std::sqrt(double(toInside[v])) - 0.5;
  return f;
}

}  // namespace

std::vector<TopologyFeature> topologyFeatures(const std::vector<std::uint8_t>& inside, const GridSpec& g) {
  if (inside.size() != std::size_t(g.count()))
    throw std::invalid_argument("topologyFeatures: the solid does not hold one value per voxel of the grid");
  if (g.count() > kMaxFeatureVoxels)
    throw std::invalid_argument("topologyFeatures: more than kMaxFeatureVoxels voxels");
  std::vector<TopologyFeature> out;
  if (std::none_of(inside.begin(), inside.end(), [](std::uint8_t v) { return v != 0; })) return out;
  Cubical complex(std::vector<unsigned>{unsigned(g.dims[0]), unsigned(g.dims[1]), unsigned(g.dims[2])},
                  signedDistance(inside, g));
  Cohomology cohomology(complex);
  cohomology.init_coefficients(2);
  cohomology.compute_persistent_cohomology(0.0);
  // A cell of the bitmap at (a, b, c) (each in [0, 2 n]) has its centre at voxel coordinates
  // ((a - 1) / 2, ...): voxels at odd positions, their faces, edges and vertices between.
  const std::size_t na = std::size_t(2 * g.dims[0] + 1), nb = std::size_t(2 * g.dims[1] + 1);
  const auto centre = [&](std::size_t cell) {
    const double a = double(cell % na), b = double((cell / na) % nb), c = double(cell / (na * nb));
    return Vec3(g.origin + g.voxel * Vec3((a - 1) / 2, (b - 1) / 2, (c - 1) / 2));
  };
  for (const auto& pair : cohomology.get_persistent_pairs()) {
    const auto birthCell = std::get<0>(pair), deathCell = std::get<1>(pair);
    const int dimension = complex.dimension(birthCell);
    if (dimension < 1) continue;
    const double birth = complex.filtration(birthCell);
    const bool dies = deathCell != complex.null_simplex();
    const double death = dies ? complex.filtration(deathCell) : std::numeric_limits<double>::infinity();
    if (!(birth <= 0 && death > 0)) continue;
    TopologyFeature f;
    f.dimension = dimension;
    f.birth_mm = birth * g.voxel;
    f.death_mm = death * g.voxel;
    f.size_mm = std::min(-f.birth_mm, f.death_mm);
    f.born_at = centre(std::size_t(birthCell));
    f.dies_at = dies ? centre(std::size_t(deathCell)) : f.born_at;
    out.push_back(f);
  }
  std::sort(out.begin(), out.end(), [](const TopologyFeature& x, const TopologyFeature& y) {
    return std::make_tuple(x.dimension, x.size_mm, x.born_at.x(), x.born_at.y(), x.born_at.z()) <
           std::make_tuple(y.dimension, y.size_mm, y.born_at.x(), y.born_at.y(), y.born_at.z());
  });
  return out;
}

}  // namespace xsect
