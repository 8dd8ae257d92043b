// Evaluation: mesh distance and side queries, surface sampling, plane cuts and their IoU, the
// accuracy metrics against analytic shapes, and `xsect eval` end to end through the binary.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <tbb/global_control.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "geometry/evaluation/mesh_distance.h"
#include "geometry/meshing/mesh_topology.h"
#include "geometry/phantoms/phantom_shape.h"
#include "geometry/evaluation/plane_cut.h"
#include "io/mesh_io.h"
#include "io/truth_file.h"
#include "cli.h"
#include "mesh_fixtures.h"
#include "pipeline/eval_metrics.h"

namespace fs = std::filesystem;
using namespace xsect;

namespace {

fs::path tempDir() { return xsect::test::freshDir("eval"); }

/// A polygon with n vertices on the circle of radius r (mm) around c, counter-clockwise.
Ring circle(const Vec2& c, double r, int n) {
  Ring ring;
  for (int i = 0; i < n; ++i)
    ring.push_back(c + r * Vec2(std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n)));
  return ring;
}

Ring rect(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

SignedDistanceFn sphereSdf(double r) {
  return [r](const Vec3& x) { return x.norm() - r; };
}

int runXsect(const std::string& args) {
  const std::string cmd = std::string(XSECT_BIN) + " " + args + " 2>/dev/null";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

nlohmann::json readJson(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

}  // namespace

// ---------------------------------------------------------------------------------------------

TEST(EvalMeshDistance, BoxDistancesClosestPointsAndSide) {
  const TriangleMesh box = test::boxMesh({0, 0, 0}, {2, 2, 2});
  const MeshDistance q(box);
  const std::vector<Vec3> pts = {{3, 1, 1}, {1, 1, 1}, {3, 3, 1}, {1, 1, 1.5}, {-1, -1, -1}};
  const std::vector<double> d = q.distances(pts);
  EXPECT_NEAR(d[0], 1.0, 1e-12);
  EXPECT_NEAR(d[1], 1.0, 1e-12);
  EXPECT_NEAR(d[2], std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(d[3], 0.5, 1e-12);
  EXPECT_NEAR(d[4], std::sqrt(3.0), 1e-12);
  EXPECT_TRUE(q.closestPoints(pts)[0].isApprox(Vec3(2, 1, 1), 1e-12));
  EXPECT_EQ(q.inside(pts), (std::vector<std::uint8_t>{0, 1, 0, 1, 0}));
}

TEST(EvalMeshDistance, InsideMatchesAnalyticSphereForManyPoints) {
  const TriangleMesh s = test::icosphere(10, 4);
  const MeshDistance q(s);
  std::vector<Vec3> pts;
  std::vector<std::uint8_t> expected;
  // A lattice avoiding the thin shell between the inscribed polyhedron and the sphere.
  for (double x = -12; x <= 12; x += 1.3)
    for (double y = -12; y <= 12; y += 1.7)
      for (double z = -12; z <= 12; z += 1.1) {
        const double r = Vec3(x, y, z).norm();
        if (std::abs(r - 10) < 0.2) continue;
        pts.emplace_back(x, y, z);
        expected.push_back(r < 10);
      }
  EXPECT_EQ(q.inside(pts), expected);
  // Distances from outside points: |x| - 10 up to the chord sagitta.
  const std::vector<double> d = q.distances({{0, 0, 20}, {13, 0, 0}});
  EXPECT_NEAR(d[0], 10.0, 0.05);
  EXPECT_NEAR(d[1], 3.0, 0.05);
}

// insideRows answers as inside() point by point: on voxel solids whose faces, edges and vertices
// the rows run through, along and in (rows on integer and half-integer lines, steps of half a
// voxel), and on a sphere and a torus along rows of random starts and directions.
TEST(EvalMeshDistance, InsideRowsAnswersAsInsidePointByPoint) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  std::size_t rowsChecked = 0;
  const auto check = [&](const TriangleMesh& mesh, const PointRows& rows) {
    const MeshDistance q(mesh);
    std::vector<Vec3> points(rows.size());
    for (std::size_t n = 0; n < rows.size(); ++n) points[n] = rows.at(n);
    const std::vector<std::uint8_t> each = q.inside(points), byRows = q.insideRows(rows);
    ASSERT_EQ(byRows.size(), each.size());
    for (std::size_t n = 0; n < each.size(); ++n)
      ASSERT_EQ(int(byRows[n]), int(each[n])) << "point " << points[n].transpose();
    rowsChecked += rows.starts.size();
  };
  for (int trial = 0; trial < 12; ++trial) {
    std::set<std::tuple<int, int, int>> voxels;
    std::uniform_int_distribution<int> c(0, 4);
    for (int v = 0; v < 30; ++v) voxels.insert({c(rng), c(rng), c(rng)});
    const TriangleMesh mesh = test::voxelBoundary(voxels);
    for (int axis = 0; axis < 3; ++axis) {
      PointRows rows;
      rows.step = Vec3::Zero();
      rows.step[axis] = 0.5;
      rows.count = 14;
      for (double a = -0.5; a <= 5.5; a += 0.5)
        for (double b = -0.5; b <= 5.5; b += 0.5) {
          Vec3 s = Vec3::Constant(-0.5);
          s[(axis + 1) % 3] = a;
          s[(axis + 2) % 3] = b;
          rows.starts.push_back(s);
        }
      check(mesh, rows);
    }
  }
  for (const TriangleMesh& mesh : {test::icosphere(6, 3), test::torusMesh(6, 2, 48, 24)}) {
    for (int trial = 0; trial < 20; ++trial) {
      PointRows rows;
      rows.step = 0.37 * Vec3(u(rng), u(rng), u(rng)).normalized();
      rows.count = 60;
      for (int r = 0; r < 40; ++r) rows.starts.push_back(Vec3(8 * u(rng), 8 * u(rng), 8 * u(rng)) - 11 * rows.step);
      check(mesh, rows);
    }
  }
  EXPECT_EQ(rowsChecked, 12u * 3 * 169 + 2 * 20 * 40);
}

TEST(EvalMeshDistance, NonManifoldSoupStillClassifies) {
  // Two unit voxels sharing only an edge: four triangles meet there (not a manifold mesh).
  const TriangleMesh m = test::voxelBoundary({{0, 0, 0}, {1, 1, 0}});
  EXPECT_FALSE(meshTopology(m).watertight);
  const MeshDistance q(m);
  EXPECT_EQ(q.inside({{0.5, 0.5, 0.5}, {1.5, 1.5, 0.5}, {1.5, 0.5, 0.5}, {0.5, 1.5, 0.3}}),
            (std::vector<std::uint8_t>{1, 1, 0, 0}));
  EXPECT_NEAR(q.distances({{1.5, 0.5, 0.5}})[0], 0.5, 1e-12);
}

TEST(EvalMeshDistance, ResultsDoNotDependOnThreadCount) {
  const TriangleMesh s = test::icosphere(5, 3);
  const std::vector<Vec3> pts = sampleSurface(test::icosphere(6, 2), 5000, 7);
  const MeshDistance q(s);
  const std::vector<double> many = q.distances(pts);
  std::vector<double> one;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = q.distances(pts);
  }
  EXPECT_EQ(many, one);
}

TEST(EvalMeshDistance, SurfaceSamplingIsSeededOnSurfaceAndAreaWeighted) {
  // A 1 x 1 x 10 box: the two end caps hold 2 of its 42 mm² of area.
  const TriangleMesh box = test::boxMesh({0, 0, 0}, {1, 1, 10});
  EXPECT_NEAR(surfaceArea(box), 42.0, 1e-9);
  const std::vector<Vec3> a = sampleSurface(box, 42000, 3);
  const std::vector<Vec3> b = sampleSurface(box, 42000, 3);
  const std::vector<Vec3> c = sampleSurface(box, 42000, 4);
  ASSERT_EQ(a.size(), 42000u);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  int caps = 0;
  for (const Vec3& p : a) {
    const double dFace = std::min({p.x(), 1 - p.x(), p.y(), 1 - p.y(), p.z(), 10 - p.z()});
    EXPECT_NEAR(dFace, 0.0, 1e-6);
    if (p.z() < 1e-9 || p.z() > 10 - 1e-6) ++caps;
  }
  EXPECT_NEAR(caps / 42000.0, 2.0 / 42.0, 0.006);
}

// ---------------------------------------------------------------------------------------------

TEST(EvalPlaneCut, CubeCutIsItsSquare) {
  const TriangleMesh box = test::boxMesh({0, 0, 0}, {2, 3, 4});
  Plane p;
  p.origin = Vec3(0, 0, 1.5);
  const auto seg = cutMesh(box, p);
  EXPECT_EQ(seg.size(), 8u);  // two triangles per side face
  EXPECT_NEAR(cutArea(seg, 0.01), 6.0, 1e-9);
  // Same square as a section: IoU 1; shifted by half its width: 1/3.
  EXPECT_NEAR(regionIoU(seg, {Section{rect(0, 0, 2, 3), {}}}, 0.01), 1.0, 1e-9);
  EXPECT_NEAR(regionIoU(seg, {Section{rect(1, 0, 3, 3), {}}}, 0.01), 1.0 / 3.0, 1e-9);
}

TEST(EvalPlaneCut, VerticesOnThePlaneStillCloseTheLoop) {
  // Two stacked unit voxels: the plane z = 1 passes exactly through a ring of vertices.
  const TriangleMesh m = test::voxelBoundary({{0, 0, 0}, {0, 0, 1}});
  Plane p;
  p.origin = Vec3(0, 0, 1);
  EXPECT_NEAR(cutArea(cutMesh(m, p), 0.01), 1.0, 1e-9);
  // Through the top or the bottom face: vertices on the plane count as above it, so the plane
  // acts as if moved infinitesimally down (closed square at the top, nothing at the bottom).
  p.origin = Vec3(0, 0, 2);
  EXPECT_NEAR(cutArea(cutMesh(m, p), 0.01), 1.0, 1e-9);
  p.origin = Vec3(0, 0, 0);
  EXPECT_TRUE(cutMesh(m, p).empty());
}

TEST(EvalPlaneCut, SphereCutMatchesExactDisk) {
  const TriangleMesh s = test::icosphere(10, 5);
  // A tilted plane at distance 6 from the centre: the cut is a disk of radius 8 around the
  // projection of the centre.
  Plane p;
  p.normal = Vec3(1, 1, 1).normalized();
  p.u = Vec3(1, -1, 0).normalized();
  p.v = p.normal.cross(p.u);
  p.origin = 6 * p.normal + 2 * p.u - 1 * p.v;  // centre at plane coordinates (-2, 1)
  const auto seg = cutMesh(s, p);
  const Vec2 c(-2, 1);
  const double iou = regionIoU(seg, {Section{circle(c, 8, 720), {}}}, 0.02);
  EXPECT_GT(iou, 0.99);
  EXPECT_LE(iou, 1.0);
  // Against a disk of radius 7 inside it: IoU = 49 / 64.
  EXPECT_NEAR(regionIoU(seg, {Section{circle(c, 7, 720), {}}}, 0.02), 49.0 / 64.0, 0.01);
  EXPECT_NEAR(cutArea(seg, 0.02), M_PI * 64, 0.01 * M_PI * 64);
}

TEST(EvalPlaneCut, ConformityWithHolesAndClip) {
  const TriangleMesh box = test::boxMesh({0, 0, 0}, {10, 10, 10});
  Plane p;
  p.origin = Vec3(0, 0, 5);
  const auto seg = cutMesh(box, p);
  // A section with a 4 x 4 hole: intersection 84, union 100.
  Section withHole{rect(0, 0, 10, 10), {rect(3, 3, 7, 7)}};
  std::reverse(withHole.holes[0].begin(), withHole.holes[0].end());  // clockwise hole
  EXPECT_NEAR(regionIoU(seg, {withHole}, 0.05), 84.0 / 100.0, 1e-9);
  // Section [5, 15] x [0, 10]: 50 / 150; clipped to x <= 10 (the observed image): 50 / 100.
  const std::vector<Section> shifted{Section{rect(5, 0, 15, 10), {}}};
  EXPECT_NEAR(regionIoU(seg, shifted, 0.05), 1.0 / 3.0, 1e-9);
  PlaneRect clip;
  clip.min = Vec2(-100, -100);
  clip.max = Vec2(10, 100);
  EXPECT_NEAR(regionIoU(seg, shifted, 0.05, &clip), 0.5, 1e-9);
  // Nothing on either side: undefined.
  Plane far;
  far.origin = Vec3(0, 0, 50);
  EXPECT_TRUE(std::isnan(regionIoU(cutMesh(box, far), {}, 0.05)));
}

// ---------------------------------------------------------------------------------------------

TEST(Eval, HausdorffOfScaledSphereIsTheOffset) {
  const double R = 10;
  const TriangleMesh mesh = test::icosphere(1.05 * R, 4);
  const MeshDistance q(mesh);
  SamplingParams sp;
  sp.surface_samples = 20000;
  sp.zero_set_starts = 20000;
  const SurfaceDistances d =
      distancesToImplicit(mesh, q, sphereSdf(R), Vec3::Constant(-12), Vec3::Constant(12), sp);
  // Vertices lie on the sphere of radius 1.05 R: mesh -> truth max is exactly 0.05 R.
  EXPECT_NEAR(d.mesh_to_truth.max_mm, 0.05 * R, 1e-5);
  EXPECT_NEAR(d.hausdorffMm(), 0.05 * R, 1e-5);
  // Truth points see the inscribed polyhedron: a little less than 0.05 R.
  EXPECT_LE(d.truth_to_mesh.max_mm, 0.05 * R + 1e-6);
  EXPECT_GT(d.truth_to_mesh.max_mm, 0.045 * R);
  EXPECT_GT(d.truth_to_mesh.points, 15000u);  // almost all starts converge on a sphere
  EXPECT_NEAR(d.meanMm(), 0.05 * R, 0.004 * R);
}

TEST(Eval, TruthSideMeanIsAreaWeighted) {
  // Mesh torus (12.3, 4.1) against the truth torus (12, 4): at tube angle b the surfaces are
  // about |0.3 cos b + 0.1| apart; weighted by area (12 + 4 cos b) the mean is 0.2225 mm. Points
  // projected from a box over-represent the outside (0.4 mm) and would give about 0.26 mm.
  const TriangleMesh mesh = test::torusMesh(12.3, 4.1, 96, 48);
  const MeshDistance q(mesh);
  const SignedDistanceFn torus = [](const Vec3& x) {
    return std::hypot(std::hypot(x.x(), x.y()) - 12, x.z()) - 4;
  };
  SamplingParams sp;
  sp.surface_samples = 20000;
  sp.zero_set_starts = 40000;
  const SurfaceDistances d = distancesToImplicit(mesh, q, torus, Vec3(-17, -17, -5),
                                                 Vec3(17, 17, 5), sp);
  EXPECT_NEAR(d.truth_to_mesh.mean_mm, 0.2225, 0.01);
  EXPECT_NEAR(d.mesh_to_truth.mean_mm, 0.2225, 0.01);
  EXPECT_NEAR(d.hausdorffMm(), 0.4, 1e-3);
}

TEST(Eval, ZeroSetPointsLieOnTheSurface) {
  const auto pts = zeroSetPoints(sphereSdf(3), Vec3::Constant(-4), Vec3::Constant(4), 2000, 5, 1e-4);
  ASSERT_GT(pts.size(), 1900u);
  for (const Vec3& p : pts) EXPECT_NEAR(p.norm(), 3.0, 1e-4);
}

TEST(Eval, HausdorffAgainstReferenceMesh) {
  const TriangleMesh a = test::icosphere(10.5, 4), b = test::icosphere(10, 4);
  const MeshDistance qa(a), qb(b);
  SamplingParams sp;
  sp.surface_samples = 20000;
  const SurfaceDistances d = distancesToMesh(a, qa, b, qb, sp);
  EXPECT_NEAR(d.hausdorffMm(), 0.5, 0.02);
  EXPECT_NEAR(d.mesh_to_truth.mean_mm, 0.5, 0.02);
  EXPECT_NEAR(d.truth_to_mesh.mean_mm, 0.5, 0.02);
}

TEST(Eval, DiceOfNestedSpheresMatchesVolumes) {
  const TriangleMesh mesh = test::icosphere(10, 4);
  const MeshDistance q(mesh);
  const double Vm = meshTopology(mesh).volume_mm3, Vs = 4.0 / 3.0 * M_PI * 7 * 7 * 7;
  const InsideFn inMesh = [&q](const PointRows& p) { return q.insideRows(p); };
  const InsideFn inSphere = [](const PointRows& p) {
    std::vector<std::uint8_t> r(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) r[i] = p.at(i).norm() < 7;
    return r;
  };
  const GridSpec grid = overlapGrid(Vec3::Constant(-10), Vec3::Constant(10), 0.3);
  const VolumeOverlap o = volumeOverlap(inMesh, inSphere, grid);
  EXPECT_NEAR(o.dice(), 2 * Vs / (Vm + Vs), 0.01);
  EXPECT_NEAR(o.iou(), Vs / Vm, 0.01);
  EXPECT_NEAR(double(o.a) * std::pow(grid.voxel, 3), Vm, 0.02 * Vm);
}

TEST(Eval, GridIsCappedAndCoversTheBox) {
  const GridSpec g = overlapGrid(Vec3(0, 0, 0), Vec3(100, 50, 10), 0.01, 1000000);
  EXPECT_LE(g.count(), 1000000);
  EXPECT_GT(g.count(), 900000);
  EXPECT_LE(g.origin.x(), 0.0);
  EXPECT_GE(g.centre(g.dims[0] - 1, 0, 0).x(), 100.0);
  const GridSpec a = overlapGrid(Vec3(0, 0, 0), Vec3(30, 40, 0), 0);
  EXPECT_NEAR(a.voxel, 0.5, 1e-12);  // 1/100 of the 50 mm diagonal
}

// ---------------------------------------------------------------------------------------------
// Through the binary.

TEST(Eval, CommandAgainstTruthWritesTheContractKeys) {
  const fs::path d = tempDir();
  writeMesh((d / "mesh.ply").string(), test::icosphere(10.5, 4));
  PhantomShape sphere;
  sphere.kind = ShapeKind::sphere;
  sphere.params["radius"] = 10;
  writeTruthFile((d / "truth.yaml").string(), sphere);
  ASSERT_EQ(runXsect("eval --mesh " + (d / "mesh.ply").string() + " --truth " +
                     (d / "truth.yaml").string() + " --json " + (d / "out.json").string() +
                     " --quiet"),
            0);
  const auto j = readJson(d / "out.json");
  EXPECT_NEAR(j.at("hausdorff_mm").get<double>(), 0.5, 1e-3);
  EXPECT_NEAR(j.at("mean_distance_mm").get<double>(), 0.5, 0.05);
  EXPECT_NEAR(j.at("mesh_to_truth_max_mm").get<double>(), 0.5, 1e-3);
  EXPECT_GT(j.at("truth_to_mesh_max_mm").get<double>(), 0.4);
  const double Vm = meshTopology(test::icosphere(10.5, 4)).volume_mm3;
  const double Vs = 4.0 / 3.0 * M_PI * 1000;
  EXPECT_NEAR(j.at("dice").get<double>(), 2 * Vs / (Vs + Vm), 0.01);
  EXPECT_NEAR(j.at("iou").get<double>(), Vs / Vm, 0.015);
  EXPECT_EQ(j.at("betti"), nlohmann::json({1, 0, 0}));
  EXPECT_EQ(j.at("truth_betti"), nlohmann::json({1, 0, 0}));
  EXPECT_TRUE(j.at("watertight").get<bool>());
  EXPECT_GT(j.at("surface_samples").get<int>(), 10000);
  EXPECT_FALSE(j.contains("conformity_iou_min"));
  // No temporary file left beside the output.
  int files = 0;
  for (const auto& e : fs::directory_iterator(d)) files += e.is_regular_file();
  EXPECT_EQ(files, 3);
  fs::remove_all(d);
}

TEST(Eval, CommandConformityWithSlices) {
  const fs::path d = tempDir();
  writeMesh((d / "mesh.stl").string(), test::icosphere(10, 4));
  // Slice 0: plane z = 3 through the sphere (a disk of radius sqrt(91)); slice 1: z = 20, empty.
  const double px = 0.25, r = std::sqrt(91.0);
  cv::Mat disk(101, 101, CV_8U), empty(101, 101, CV_8U, cv::Scalar(0));
  for (int j = 0; j < 101; ++j)
    for (int i = 0; i < 101; ++i)
      disk.at<std::uint8_t>(j, i) = std::hypot(i * px - 12.5, j * px - 12.5) < r ? 255 : 0;
  ASSERT_TRUE(cv::imwrite((d / "disk.png").string(), disk));
  ASSERT_TRUE(cv::imwrite((d / "empty.png").string(), empty));
  std::ofstream((d / "slices.yaml").string())
      << "slices:\n"
         "  - image: disk.png\n"
         "    image_to_world: [[0.25, 0, 0, -12.5], [0, 0.25, 0, -12.5], [0, 0, 0, 3], [0, 0, 0, 1]]\n"
         "  - image: empty.png\n"
         "    image_to_world: [[0.25, 0, 0, -12.5], [0, 0.25, 0, -12.5], [0, 0, 0, 20], [0, 0, 0, 1]]\n";
  ASSERT_EQ(runXsect("eval --mesh " + (d / "mesh.stl").string() + " --reference " +
                     (d / "mesh.stl").string() + " --slices " + (d / "slices.yaml").string() +
                     " --json " + (d / "out.json").string() + " --quiet"),
            0);
  const auto j = readJson(d / "out.json");
  EXPECT_NEAR(j.at("hausdorff_mm").get<double>(), 0.0, 1e-9);  // the reference is the mesh
  EXPECT_NEAR(j.at("dice").get<double>(), 1.0, 1e-12);
  const auto& c = j.at("conformity");
  ASSERT_EQ(c.size(), 2u);
  EXPECT_GT(c[0].at("iou").get<double>(), 0.95);
  EXPECT_NEAR(c[0].at("section_area_mm2").get<double>(), M_PI * 91, 0.03 * M_PI * 91);
  EXPECT_TRUE(c[1].at("iou").is_null());
  EXPECT_EQ(j.at("conformity_iou_min").get<double>(), c[0].at("iou").get<double>());
  fs::remove_all(d);
}

TEST(Eval, MalformedInputsExitWithCode2) {
  const fs::path d = tempDir();
  const std::string good = (d / "good.ply").string();
  writeMesh(good, test::icosphere(10, 1));
  std::ofstream((d / "bad.ply").string()) << "ply\nformat ascii 1.0\nelement vertex 3\n";
  std::ofstream((d / "bad.obj").string()) << "v 0 0 0\nf 1 2 3\n";
  std::ofstream((d / "bad.yaml").string()) << "shape: [1, 2\n";
  const std::string json = " --json " + (d / "out.json").string() + " --quiet";
  EXPECT_EQ(runXsect("eval --mesh " + (d / "bad.ply").string() + " --reference " + good + json), 2);
  EXPECT_EQ(runXsect("eval --mesh " + good + " --reference " + (d / "bad.obj").string() + json), 2);
  EXPECT_EQ(runXsect("eval --mesh " + (d / "missing.stl").string() + " --reference " + good + json), 2);
  EXPECT_EQ(runXsect("eval --mesh " + good + " --truth " + (d / "bad.yaml").string() + json), 2);
  EXPECT_EQ(runXsect("eval --mesh " + good + " --reference " + good + " --voxel=-1" + json), 2);
  EXPECT_EQ(runXsect("eval --mesh " + good + " --reference " + good + " --slices " +
                     (d / "missing.yaml").string() + json),
            2);
  EXPECT_FALSE(fs::exists(d / "out.json"));  // nothing written on failure
  fs::remove_all(d);
}
