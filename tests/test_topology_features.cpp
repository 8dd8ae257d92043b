// The handles and cavities of voxel solids with their persistence
// (geometry/reconstruction/topology_features.h): as many tunnels and cavities as voxelBetti counts,
// on random sets; a torus' tunnel as large as its tube and hole allow, a thin rod across its hole a
// tunnel of the rod's size at the rod; a hollow ball's cavity as large as its shell.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/core/digital_topology.h"
#include "geometry/reconstruction/topology_features.h"

namespace xsect {
namespace {

GridSpec cube(int n, double voxel) {
  GridSpec g;
  g.voxel = voxel;
  g.dims = {n, n, n};
  g.origin = Vec3::Constant(-voxel * (n - 1) / 2.0);
  return g;
}

std::vector<std::uint8_t> solid(const GridSpec& g, const std::function<bool(const Vec3&)>& in) {
  std::vector<std::uint8_t> s(std::size_t(g.count()), 0);
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) s[std::size_t(g.index(i, j, k))] = in(g.centre(i, j, k));
  return s;
}

TEST(TopologyFeatures, AsManyTunnelsAndCavitiesAsTheBettiNumbersOnRandomSets) {
  std::mt19937 rng(41);
  int tunnels = 0, cavities = 0;
  for (const double density : {0.3, 0.5, 0.7}) {
    for (int trial = 0; trial < 10; ++trial) {
      GridSpec g;
      g.dims = {5 + int(rng() % 8), 5 + int(rng() % 8), 5 + int(rng() % 8)};
      std::bernoulli_distribution on(density);
      std::vector<std::uint8_t> in(std::size_t(g.count()), 0);
      for (int k = 1; k + 1 < g.dims[2]; ++k)  // an empty margin
        for (int j = 1; j + 1 < g.dims[1]; ++j)
          for (int i = 1; i + 1 < g.dims[0]; ++i) in[std::size_t(g.index(i, j, k))] = on(rng);
      const Betti b = voxelBetti(in, g);
      int dims[3] = {0, 0, 0};
      for (const TopologyFeature& f : topologyFeatures(in, g)) {
        ++dims[f.dimension];
        EXPECT_LE(f.birth_mm, 0);
        EXPECT_GT(f.death_mm, 0);
        EXPECT_EQ(f.size_mm, std::min(-f.birth_mm, f.death_mm));
      }
      EXPECT_EQ(dims[1], b[1]) << "density " << density << " trial " << trial;
      EXPECT_EQ(dims[2], b[2]) << "density " << density << " trial " << trial;
      tunnels += b[1], cavities += b[2];
    }
  }
  EXPECT_GT(tunnels, 10);  // the sets do have tunnels and cavities: the test can fail
  EXPECT_GT(cavities, 3);
}

TEST(TopologyFeatures, ATorusTunnelHasItsTubesSizeAndAThinRodAcrossItsHoleARodsSize) {
  const double voxel = 0.5, R = 8, a = 3;  // ring and tube radii, mm
  const GridSpec g = cube(48, voxel);
  const auto torus = [&](const Vec3& x) { return std::hypot(std::hypot(x.x(), x.y()) - R, x.z()) <= a; };
  const std::vector<TopologyFeature> one = topologyFeatures(solid(g, torus), g);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].dimension, 1);
  // Eroding by the tube's radius or growing by the hole's (R - a = 5 mm) removes it: the smaller.
  EXPECT_NEAR(one[0].size_mm, a, 1.5 * voxel);
  EXPECT_NEAR(-one[0].birth_mm, a, 1.5 * voxel);
  EXPECT_NEAR(one[0].death_mm, R - a, 1.5 * voxel);
  // A rod of radius 0.5 mm across the hole along x: one more tunnel, of about the rod's radius,
  // born on the rod.
  const auto rod = [&](const Vec3& x) { return torus(x) || (std::abs(x.x()) < R && std::hypot(x.y(), x.z()) <= 0.6); };
  const std::vector<TopologyFeature> two = topologyFeatures(solid(g, rod), g);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_LE(two[0].size_mm, 1.0);
  EXPECT_LT(std::hypot(two[0].born_at.y(), two[0].born_at.z()), 1.0);  // on the rod
  EXPECT_LT(std::abs(two[0].born_at.x()), R - a);
  EXPECT_NEAR(two[1].size_mm, a, 1.5 * voxel);  // the torus' own tunnel stays large
}

TEST(TopologyFeatures, AHollowBallsCavityIsAsLargeAsItsShell) {
  const double voxel = 0.5;
  const GridSpec g = cube(40, voxel);
  const std::vector<TopologyFeature> f =
      topologyFeatures(solid(g, [](const Vec3& x) { return x.norm() <= 8 && x.norm() >= 6; }), g);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].dimension, 2);
  EXPECT_NEAR(-f[0].birth_mm, 1.0, 1.5 * voxel);  // eroding the 2 mm shell by 1 mm opens it
  EXPECT_NEAR(f[0].death_mm, 6.0, 1.5 * voxel);   // growing by the cavity's radius fills it
  EXPECT_LT(f[0].dies_at.norm(), 1.5);             // at the cavity's centre
  EXPECT_THROW(topologyFeatures(std::vector<std::uint8_t>(3, 0), g), std::invalid_argument);
}

}  // namespace
}  // namespace xsect
