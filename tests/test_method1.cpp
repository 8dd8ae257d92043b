// Method 1 (thesis ch. 1, Def. 15-17) on analytic sections: topology and distance to the truth.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "geometry/meshing/conformal_cut.h"
#include "geometry/meshing/mesh_topology.h"
#include "geometry/evaluation/plane_cut.h"
#include "geometry/core/polygon.h"
#include "geometry/reconstruction/sampled_reconstruction.h"
#include "geometry/meshing/volume_mesher.h"
#include "section_fixtures.h"

using namespace xsect;

namespace {

struct Result {
  SampledReconstruction rec;
  TriangleMesh mesh;
  MeshTopology topo;
};

Result run(const std::vector<CuttingPlane>& planes, double voxel) {
  Result r;
  ReconstructionParams p;
  p.voxel_mm = voxel;
  r.rec = reconstructOnGrid(sectionScene(planes, p));
  r.mesh = meshZeroLevel(r.rec.field);
  r.topo = meshTopology(r.mesh);
  return r;
}

}  // namespace

TEST(Method1, BallMultiaxialHasBallTopologyAndIsClose) {
  const double R = 10, gap = 2.5;
  const auto planes = test::multiaxialShell(Vec3(1, 2, 3), R, 0, gap, 12);
  const Result r = run(planes, 0.25);
  EXPECT_TRUE(r.topo.watertight);
  EXPECT_EQ(r.topo.betti, (Betti{1, 0, 0}));
  EXPECT_EQ(r.rec.voxel_betti, (Betti{1, 0, 0}));
  double worst = 0;
  for (const auto& v : r.mesh.vertices)
    worst = std::max(worst, std::abs((v.cast<double>() - Vec3(1, 2, 3)).norm() - R));
  EXPECT_LT(worst, gap);  // Hausdorff (mesh -> truth) below the largest gap between planes
  // Tighter: a point of ∂R is within about the cell height (gap/2 for cubic cells) of ∂O.
  EXPECT_LT(worst, 0.5 * gap + 0.25);
}

TEST(Method1, HollowBallKeepsItsCavity) {
  const auto planes = test::multiaxialShell(Vec3(0, 0, 0), 10, 5, 2.0, 12);
  const Result r = run(planes, 0.25);
  EXPECT_TRUE(r.topo.watertight);
  EXPECT_EQ(r.topo.betti, (Betti{1, 0, 1}));
}

TEST(Method1, TwoBallsStayApart) {
  // One set of planes; each plane's sections are those of both balls (3 mm apart).
  auto a = test::multiaxialShell(Vec3::Zero(), 0, 0, 1.5, 14);
  for (auto& cp : a)
    for (const double x : {-6.5, 6.5}) {
      const auto s = test::shellSections(cp.plane, Vec3(x, 0, 0), 5, 0);
      cp.sections.insert(cp.sections.end(), s.begin(), s.end());
    }
  const Result r = run(a, 0.25);
  EXPECT_EQ(r.topo.betti, (Betti{2, 0, 0}));
}

TEST(Method1, OpenStackEndsWithinTheMargin) {
  // A z-stack that starts and ends inside the ball: no empty end slice.
  std::vector<CuttingPlane> planes;
  const double R = 10, margin = 3;
  for (double z = -6; z <= 6.01; z += 2) {
    CuttingPlane cp;
    cp.slice = int(planes.size());
    cp.plane = test::axisPlane(2, z);
    cp.sections = test::shellSections(cp.plane, Vec3::Zero(), R, 0);
    planes.push_back(cp);
  }
  ReconstructionParams p;
  p.voxel_mm = 0.25;
  p.end_margin_mm = margin;
  const auto rec = reconstructOnGrid(sectionScene(planes, p));
  const TriangleMesh mesh = meshZeroLevel(rec.field);
  const MeshTopology topo = meshTopology(mesh);
  EXPECT_TRUE(topo.watertight);
  EXPECT_EQ(topo.betti, (Betti{1, 0, 0}));
  test::expectEndsHalfWayToEndPlanes(mesh, -6.0, 6.0, margin);
}

TEST(Method1, ConformalCutPutsTheCutOnTheContoursWithoutFolding) {
  const double R = 10;
  const auto planes = test::multiaxialShell(Vec3(0.2, -0.1, 0.3), R, 0, 2.0, 12);
  ReconstructionParams p;
  p.voxel_mm = 0.3;
  const SectionScene scene = sectionScene(planes, p);
  const auto rec = reconstructOnGrid(scene);
  TriangleMesh mesh = meshZeroLevel(rec.field);
  const MeshTopology before = meshTopology(mesh);
  const ConformalCutStats stats = cutAlongSections(mesh, planes, scene.fields, p.voxel_mm);
  const MeshTopology after = meshTopology(mesh);
  EXPECT_TRUE(after.watertight);
  EXPECT_EQ(after.betti, before.betti);
  EXPECT_GT(stats.vertices_added, 1000);
  EXPECT_GT(stats.vertices_snapped, 0.9 * stats.vertices_added);
  // Folds: adjacent triangles whose normals oppose (dot < -0.5) stay rare.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::size_t> edge;
  int folded = 0, pairs = 0;
  const auto normal = [&](std::size_t t) {
    const auto& T = mesh.triangles[t];
    const Eigen::Vector3f a = mesh.vertices[T[0]], b = mesh.vertices[T[1]], c = mesh.vertices[T[2]];
    return Eigen::Vector3f((b - a).cross(c - a).normalized());
  };
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int e = 0; e < 3; ++e) {
      const auto a = mesh.triangles[t][e], b = mesh.triangles[t][(e + 1) % 3];
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      const auto it = edge.find(key);
      if (it == edge.end()) {
        edge.emplace(key, t);
      } else {
        ++pairs;
        folded += normal(t).dot(normal(it->second)) < -0.5f;
      }
    }
  EXPECT_LT(folded, 0.002 * pairs) << folded << " folded of " << pairs;
  // The cut of the mesh by each plane: its area is the analytic disk's within 1%.
  for (const auto& cp : planes) {
    if (cp.sections.empty()) continue;
    const double want = sectionArea(cp.sections[0]);
    if (want < M_PI * 9) continue;  // sections at least 6 mm across (20 voxels)
    const double got = cutArea(cutMesh(mesh, cp.plane), 0.02);
    EXPECT_NEAR(got, want, 0.01 * want) << "plane " << cp.slice;
  }
}
