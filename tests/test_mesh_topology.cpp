// Topology of meshes built here: watertightness, surfaces, Betti numbers of the bounded solid
// and enclosed volume.
#include <gtest/gtest.h>

#include "geometry/meshing/mesh_topology.h"
#include "mesh_fixtures.h"

using namespace xsect;
using test::boxMesh;

TEST(MeshTopology, CubeIsABall) {
  const MeshTopology t = meshTopology(boxMesh({0, 0, 0}, {2, 3, 4}));
  EXPECT_TRUE(t.watertight);
  EXPECT_EQ(t.surfaces, 1);
  EXPECT_EQ(t.betti, (Betti{1, 0, 0}));
  EXPECT_NEAR(t.volume_mm3, 24.0, 1e-9);
}

TEST(MeshTopology, TorusHasOneTunnel) {
  const MeshTopology t = meshTopology(test::torusMesh(10, 3, 32, 16));
  EXPECT_TRUE(t.watertight);
  EXPECT_EQ(t.surfaces, 1);
  EXPECT_EQ(t.betti, (Betti{1, 1, 0}));
  // Inscribed polyhedron: a little less than 2 pi^2 R r^2.
  const double exact = 2 * M_PI * M_PI * 10 * 9;
  EXPECT_LT(t.volume_mm3, exact);
  EXPECT_GT(t.volume_mm3, 0.95 * exact);
}

TEST(MeshTopology, CubeWithCavity) {
  TriangleMesh m = boxMesh({0, 0, 0}, {10, 10, 10});
  test::append(&m, boxMesh({4, 4, 4}, {6, 6, 6}, /*inverted=*/true));
  const MeshTopology t = meshTopology(m);
  EXPECT_TRUE(t.watertight);
  EXPECT_EQ(t.surfaces, 2);
  EXPECT_EQ(t.betti, (Betti{1, 0, 1}));
  EXPECT_NEAR(t.volume_mm3, 1000.0 - 8.0, 1e-9);
}

TEST(MeshTopology, TwoCubesAreTwoComponents) {
  TriangleMesh m = boxMesh({0, 0, 0}, {1, 1, 1});
  test::append(&m, boxMesh({3, 0, 0}, {4, 1, 1}));
  const MeshTopology t = meshTopology(m);
  EXPECT_TRUE(t.watertight);
  EXPECT_EQ(t.surfaces, 2);
  EXPECT_EQ(t.betti, (Betti{2, 0, 0}));
}

TEST(MeshTopology, VoxelSlabWithTwoHolesHasGenusTwo) {
  // 5 x 3 x 1 voxels with voxels (1, 1) and (3, 1) removed: a figure-eight plate.
  std::set<std::tuple<int, int, int>> voxels;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 3; ++j)
      if (!(j == 1 && (i == 1 || i == 3))) voxels.insert({i, j, 0});
  const MeshTopology t = meshTopology(test::voxelBoundary(voxels));
  EXPECT_TRUE(t.watertight);
  EXPECT_EQ(t.surfaces, 1);
  EXPECT_EQ(t.betti, (Betti{1, 2, 0}));
  EXPECT_NEAR(t.volume_mm3, 13.0, 1e-9);
}

TEST(MeshTopology, OpenMeshIsNotWatertight) {
  TriangleMesh m = boxMesh({0, 0, 0}, {1, 1, 1});
  m.triangles.pop_back();
  EXPECT_FALSE(meshTopology(m).watertight);
}

TEST(MeshTopology, FlippedTriangleIsNotWatertight) {
  TriangleMesh m = boxMesh({0, 0, 0}, {1, 1, 1});
  std::swap(m.triangles[3][1], m.triangles[3][2]);
  const MeshTopology t = meshTopology(m);
  EXPECT_FALSE(t.watertight);
  EXPECT_EQ(t.surfaces, 1);
}

TEST(MeshTopology, InvertedCubeIsACavityAlone) {
  const MeshTopology t = meshTopology(boxMesh({0, 0, 0}, {1, 1, 1}, true));
  EXPECT_EQ(t.betti, (Betti{0, 0, 1}));
  EXPECT_NEAR(t.volume_mm3, -1.0, 1e-12);
}
