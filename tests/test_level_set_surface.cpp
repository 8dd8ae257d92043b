// Issue 14, "the mesh written is the solid reported": the level set and mesh of a field keep its
// cavities and components (the cause of the lost cavity was OpenVDB's levelSetRebuild re-signing
// the band from the outside), and the mesh of a well-composed solid has its voxels' Betti numbers.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/core/digital_topology.h"
#include "geometry/meshing/mesh_topology.h"
#include "geometry/meshing/volume_mesher.h"

using namespace xsect;

namespace {

/// Dense field of the shell Ri < |x| < Ro (negative inside), not a distance beyond its scale:
/// (|x| - Ro)(|x| - Ri) / Ro, as smooth fields such as Shepard's are.
ScalarField shellField(double Ro, double Ri, double h) {
  ScalarField f;
  const int n = int(std::ceil(2 * (Ro + 3 * h) / h)) + 1;
  f.grid.voxel = h;
  f.grid.dims = {n, n, n};
  f.grid.origin = Vec3::Constant(-(n - 1) * h / 2);
  f.values.resize(std::size_t(f.grid.count()));
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double r = f.grid.centre(i, j, k).norm();
        f.values[std::size_t(f.grid.index(i, j, k))] = float((r - Ro) * (r - Ri) / Ro);
      }
  return f;
}

}  // namespace

TEST(LevelSetSurface, KeepsTheCavityOfAHollowField) {
  for (const double h : {0.25, 0.4, 0.6}) {
    SCOPED_TRACE(h);
    const ScalarField f = shellField(6.0, 3.5, h);
    const LevelSetSurface s = levelSetSurface(f, 3.0, 0.0);
    const MeshTopology t = meshTopology(s.mesh);
    EXPECT_TRUE(t.watertight);
    EXPECT_EQ(t.betti, (Betti{1, 0, 1}));
    // The band holds the inner surface: active voxels on both sides of r = Ri, signed as the
    // shell's (inside between the radii), their magnitude the distance to the surface.
    int innerInside = 0, innerOutside = 0;
    double worst = 0;
    for (std::size_t q = 0; q < s.level_set.coords.size(); ++q) {
      const auto& c = s.level_set.coords[q];
      const double r = s.level_set.grid.centre(c[0], c[1], c[2]).norm();
      const double sd = std::abs(r - 6.0) < std::abs(r - 3.5) ? r - 6.0 : 3.5 - r;
      if (std::abs(r - 3.5) < 2 * h) (s.level_set.values[q] < 0 ? innerInside : innerOutside)++;
      worst = std::max(worst, std::abs(double(s.level_set.values[q]) - sd));
    }
    EXPECT_GT(innerInside, 100);
    EXPECT_GT(innerOutside, 100);
    EXPECT_LT(worst, 0.5 * h);  // the mesh is within a fraction of a voxel of the spheres
  }
}

TEST(LevelSetSurface, MeshHasTheVoxelBettiNumbersOfAWellComposedSolid) {
  // Random blobs: the solid made well-composed, its mesh has the voxel set's Betti numbers.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 12; ++trial) {
    ScalarField f;
    f.grid.voxel = 1.0;
    f.grid.dims = {24, 24, 24};
    f.values.assign(std::size_t(f.grid.count()), 1.0f);
    std::vector<Vec3> centres;
    for (int b = 0; b < 10; ++b) centres.emplace_back(12 + 8 * u(rng), 12 + 8 * u(rng), 12 + 8 * u(rng));
    for (int k = 1; k < 23; ++k)
      for (int j = 1; j < 23; ++j)
        for (int i = 1; i < 23; ++i) {
          double v = 1e9;
          for (const Vec3& c : centres) v = std::min(v, (Vec3(i, j, k) - c).norm() - 2.6);
          f.values[std::size_t(f.grid.index(i, j, k))] = float(v);
        }
    std::vector<std::uint8_t> in(f.values.size());
    for (std::size_t q = 0; q < in.size(); ++q) in[q] = f.values[q] < 0;
    makeWellComposed(in, f.grid);
    imposeSolid(f, in, 0.05f);
    const LevelSetSurface s = levelSetSurface(f, 3.0, 0.0);
    const MeshTopology t = meshTopology(s.mesh);
    EXPECT_TRUE(t.watertight) << trial;
    EXPECT_EQ(t.betti, voxelBetti(in, f.grid)) << trial;
  }
}
