// reconstruction.topology (issue 51, geometry/reconstruction/topology_control.h): the solid the
// sections allow with the topology asked for, chosen cell by cell by cutting and adding joins,
// whose cut by every plane stays that plane's sections; refusals name the key.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "geometry/evaluation/plane_cut.h"
#include "io/csl_file.h"
#include "io/mesh_io.h"
#include "phantom_runs.h"

namespace xsect {
namespace {

namespace fs = std::filesystem;

Section disk(double x, double y, double r) {
  Section s;
  for (int k = 0; k < 96; ++k) {
    const double a = 2 * M_PI * k / 96;
    s.outer.push_back(Vec2(x + r * std::cos(a), y + r * std::sin(a)));
  }
  return s;
}

CuttingPlane horizontal(int slice, double z, std::vector<Section> sections) {
  CuttingPlane p;
  p.slice = slice;
  p.name = "z=" + std::to_string(z);
  p.plane.origin = Vec3(0, 0, z);
  p.plane.normal = Vec3::UnitZ();
  p.plane.u = Vec3::UnitX();
  p.plane.v = Vec3::UnitY();
  p.sections = std::move(sections);
  return p;
}

/// Two parallel planes 10 mm apart: disks A (-6, 0) and B (6, 0) below, C (0, 6) and D (0, -7.2)
/// above, radius 5. Method 1 joins A-C, C-B, B-D and D-A half-way between the planes, where the
/// disks' projections overlap: a ring (1, 1, 0), whose joins with D are the thinnest (0.6 mm
/// overlaps against 1.5 mm).
fs::path fourDiskRing() {
  const fs::path dir = test::freshDir("topology-ring");
  writeCslFile((dir / "ring.csl").string(), {horizontal(0, 0, {disk(-6, 0, 5), disk(6, 0, 5)}),
                                             horizontal(1, 10, {disk(0, 6, 5), disk(0, -7.2, 5)})});
  test::writeFile(dir / "config.yaml",
                  "input:\n  csl: ring.csl\nreconstruction:\n  voxel_size_mm: 0.25\noutput:\n  mesh: [ply]\n");
  return dir;
}

/// Every mend (gap_filled, neck_cut) of report.json's topology.changes keeps b0 and makes no
/// tunnel nor cavity: only joins may make them (a mend's would be about a voxel wide).
void expectMendsOnlyRemoveFeatures(const nlohmann::json& topology, const std::string& tag) {
  nlohmann::json before = topology["betti_before"];
  for (const auto& c : topology["changes"]) {
    if (c["change"] == "gap_filled" || c["change"] == "neck_cut") {
      EXPECT_EQ(c["betti_after"][0], before[0]) << tag << " " << c.dump();
      EXPECT_LE(c["betti_after"][1], before[1]) << tag << " " << c.dump();
      EXPECT_LE(c["betti_after"][2], before[2]) << tag << " " << c.dump();
    }
    before = c["betti_after"];
  }
}

nlohmann::json runRing(const fs::path& dir, const std::string& out, const std::string& sets) {
  const auto r = test::runXsect("run " + (dir / "config.yaml").string() + " --out " + (dir / out).string() +
                                " --quiet " + sets);
  EXPECT_EQ(r.code, 0) << r.err;
  return test::readJson(dir / out / "report.json");
}

/// The IoU of the mesh's cut by each input plane with that plane's sections.
std::vector<double> cutIoUs(const fs::path& mesh, const std::vector<CuttingPlane>& planes) {
  const TriangleMesh m = readMesh(mesh.string());
  std::vector<double> out;
  for (const CuttingPlane& p : planes) out.push_back(regionIoU(cutMesh(m, p.plane), p.sections, 0.05));
  return out;
}

TEST(TopologyControl, ARingOfFourJoinsIsCutAtItsThinnestJoinAndKeepsEveryPlanesSections) {
  const fs::path dir = fourDiskRing();
  const std::vector<CuttingPlane> planes = readCslFile((dir / "ring.csl").string());
  const nlohmann::json free = runRing(dir, "free", "");
  ASSERT_EQ(free["betti"], nlohmann::json({1, 1, 0}));
  EXPECT_EQ(free["topology"]["mode"], "free");  // the confidence only (issue 52): nothing changed
  EXPECT_FALSE(free["topology"].contains("changes"));
  const std::vector<double> freeIoU = cutIoUs(dir / "free/mesh.ply", planes);

  for (const std::string mode : {"[1,0,0]", "simplest"}) {
    const nlohmann::json r = runRing(dir, "ball", "--set reconstruction.topology=" + mode);
    EXPECT_EQ(r["betti"], nlohmann::json({1, 0, 0})) << mode;
    const nlohmann::json& t = r["topology"];
    EXPECT_EQ(t["betti_before"], nlohmann::json({1, 1, 0}));
    EXPECT_EQ(t["betti_after"], r["betti"]);
    ASSERT_EQ(t["changes"].size(), 1u) << t.dump();
    const nlohmann::json& cut = t["changes"][0];
    EXPECT_EQ(cut["change"], "join_cut");
    // A thin join, with D (flat id 3: A 0, B 1 below, C 2, D 3 above), half-way between the planes.
    EXPECT_EQ(cut["sections"][1], 3) << cut.dump();
    EXPECT_NEAR(cut["at_mm"][2].get<double>(), 5.0, 0.5);
    EXPECT_LT(cut["at_mm"][1].get<double>(), 0.0);
    // One solid: labels.nrrd's and the mesh's Betti numbers are the ones reported.
    EXPECT_EQ(r["voxel_betti"], r["betti"]);
    // Every plane's cut is still its sections.
    const std::vector<double> iou = cutIoUs(dir / "ball/mesh.ply", planes);
    for (std::size_t p = 0; p < planes.size(); ++p) {
      EXPECT_GT(iou[p], 0.97) << mode << " plane " << p;
      EXPECT_GT(iou[p], freeIoU[p] - 0.01) << mode << " plane " << p;
    }
    // graph.json: the join cut is no edge of the method's graph any more.
    const nlohmann::json g = test::readJson(dir / "ball/graph.json");
    int withD = 0;
    for (const auto& e : g["edges"])
      if (e["method"] == "nearest_plane" && (e["a"] == 3 || e["b"] == 3)) ++withD;
    EXPECT_EQ(withD, 1) << g["edges"].dump();
    fs::remove_all(dir / "ball");
  }

  // Two components: the ring cut twice (a bridge once the ring is open).
  const nlohmann::json two = runRing(dir, "two", "--set reconstruction.topology=[2,0,0]");
  EXPECT_EQ(two["betti"], nlohmann::json({2, 0, 0}));
  EXPECT_EQ(two["topology"]["changes"].size(), 2u);
  // The page shows the cells changed, and only when the topology was controlled.
  const std::string page = test::slurp(dir / "two/report.html");
  EXPECT_NE(page.find("<section id=\"topology\">"), std::string::npos);
  EXPECT_NE(page.find("join_cut"), std::string::npos);
  EXPECT_EQ(test::slurp(dir / "free/report.html").find("<section id=\"topology\">"), std::string::npos);
}

/// An annulus between radii r0 and r1 on a horizontal plane.
Section annulus(double r0, double r1) {
  Section s = disk(0, 0, r1);
  Ring hole = disk(0, 0, r0).outer;
  std::reverse(hole.begin(), hole.end());
  s.holes.push_back(hole);
  return s;
}

/// A frustum's wall, 1 mm thick (radii 9-10 mm at z = 0, 10.5-11.5 mm at z = 10), cut by its two
/// end planes and by the axial planes y = 0 and x = 0. Method 1 lifts each end's annulus half-way:
/// in each of the four quadrant cells between the end planes the two halves of the wall miss each
/// other by 0.5 mm, held together by the axial planes' sections: b1 = 5, the wall's own tunnel
/// and four gaps (the mug's case, synthetic). Mends fill the four gaps.
TEST(TopologyControl, TheGapsBetweenAWallsHalvesAreFilledCellByCell) {
  const fs::path dir = test::freshDir("topology-frustum");
  const auto axial = [](int slice, const Vec3& normal, const Vec3& u) {
    CuttingPlane p;
    p.slice = slice;
    p.name = "axial " + std::to_string(slice);
    p.plane.origin = Vec3::Zero();
    p.plane.normal = normal;
    p.plane.u = u;
    p.plane.v = Vec3::UnitZ();
    for (const double side : {1.0, -1.0}) {
      Section s;
      s.outer = {Vec2(9 * side, 0), Vec2(10 * side, 0), Vec2(11.5 * side, 10), Vec2(10.5 * side, 10)};
      if (side < 0) std::reverse(s.outer.begin(), s.outer.end());
      p.sections.push_back(s);
    }
    return p;
  };
  const std::vector<CuttingPlane> planes{horizontal(0, 0, {annulus(9, 10)}), horizontal(1, 10, {annulus(10.5, 11.5)}),
                                         axial(2, Vec3::UnitY(), Vec3::UnitX()), axial(3, Vec3::UnitX(), Vec3::UnitY())};
  writeCslFile((dir / "frustum.csl").string(), planes);
  test::writeFile(dir / "config.yaml",
                  "input:\n  csl: frustum.csl\nreconstruction:\n  voxel_size_mm: 0.35\noutput:\n  mesh: [ply]\n");
  const nlohmann::json free = runRing(dir, "free", "");
  ASSERT_EQ(free["betti"], nlohmann::json({1, 5, 0}));
  const std::vector<double> freeIoU = cutIoUs(dir / "free/mesh.ply", readCslFile((dir / "frustum.csl").string()));
  const nlohmann::json r = runRing(dir, "target", "--set reconstruction.topology=[1,1,0]");
  EXPECT_EQ(r["betti"], nlohmann::json({1, 1, 0}));
  EXPECT_EQ(r["voxel_betti"], r["betti"]);
  int filled = 0;
  for (const auto& c : r["topology"]["changes"]) {
    filled += c["change"] == "gap_filled";
    if (c["change"] == "gap_filled") EXPECT_GE(c["sections"].size(), 2u) << c.dump();  // it joins the halves
  }
  EXPECT_EQ(filled, 4) << r["topology"].dump();
  // The one tunnel left is the wall's own, as large as the wall (1 mm) lets it be.
  ASSERT_EQ(r["topology"]["features"].size(), 1u) << r["topology"]["features"].dump();
  EXPECT_EQ(r["topology"]["features"][0]["kind"], "tunnel");
  EXPECT_GE(r["topology"]["features"][0]["size_mm"].get<double>(), 0.25);
  const std::vector<double> iou = cutIoUs(dir / "target/mesh.ply", readCslFile((dir / "frustum.csl").string()));
  for (std::size_t p = 0; p < iou.size(); ++p) EXPECT_GE(iou[p], freeIoU[p] - 0.01) << "plane " << p;
}

TEST(TopologyControl, FreeIsTheMethodsOwnSolidByteForByte) {
  const fs::path dir = fourDiskRing();
  runRing(dir, "plain", "");
  runRing(dir, "free", "--set reconstruction.topology=free");
  for (const char* f : {"mesh.ply", "labels.nrrd", "graph.json"})
    EXPECT_EQ(test::slurp(dir / "plain" / f), test::slurp(dir / "free" / f)) << f;
}

TEST(TopologyControl, AnUnreachableTargetAndUnsupportedSettingsAreRefusedNamingTheKey) {
  const fs::path dir = fourDiskRing();
  // Five components from four sections.
  const auto expectRefused = [&](const std::string& sets, const std::string& key) {
    const auto r = test::runXsect("run " + (dir / "config.yaml").string() + " --out " + (dir / "out").string() + " " + sets);
    EXPECT_EQ(r.code, 2) << sets << "\n" << r.err;
    EXPECT_NE(r.err.find(key), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out")) << sets;
  };
  expectRefused("--set reconstruction.topology=[5,0,0]", "reconstruction.topology");
  expectRefused("--set reconstruction.topology=[0,0,0]", "reconstruction.topology[0]");
  expectRefused("--set reconstruction.topology=[1,0]", "reconstruction.topology");
  expectRefused("--set reconstruction.topology=round", "reconstruction.topology");
  expectRefused("--set reconstruction.topology=[1,0,0] --set reconstruction.method=delaunay", "reconstruction.topology");
  expectRefused("--set reconstruction.topology=simplest --set smoothing.method=shepard", "reconstruction.topology");
  expectRefused("--set reconstruction.min_feature_mm=2", "reconstruction.min_feature_mm");
}

}  // namespace
}  // namespace xsect

namespace xsect {
namespace {

/// A spec of configs/phantoms' torus (R 12, r 4 mm) or genus-2 solid cut by `count` random planes.
std::string sparseSpec(const std::string& shape, int count, int seed) {
  const std::string s =
      shape == "torus" ? "shape: {kind: torus, params: {major_radius: 12, minor_radius: 4}, rotation_deg: [20, 10, 0]}\n"
                       : "shape:\n  kind: genus2\n  params: {disk_radius: 20, hole_radius: 5, hole_offset: 8, "
                         "offset_radius: 2.5}\n  rotation_deg: [30, 0, 15]\n";
  return "seed: " + std::to_string(seed) + "\n" + s + "pattern: {kind: random, count: " + std::to_string(count) +
         "}\nimage: {pixel_mm: 0.25}\nconfig: {reconstruction: {voxel_size_mm: 0.4}}\n";
}

TEST(TopologyControlFamilies, SparseToriAndGenusTwoSolidsReachTheTruthsBettiNumbers) {
  int configs = 0, reached = 0, freeRight = 0;
  std::string failures;
  for (const auto& [shape, count] : std::vector<std::pair<std::string, int>>{{"torus", 6}, {"torus", 9}, {"genus2", 20},
                                                                            {"genus2", 30}})
    for (int seed = 1; seed <= 4; ++seed) {
      const std::string tag = "topology-" + shape + "-" + std::to_string(count) + "-" + std::to_string(seed);
      const fs::path dir = test::phantom(tag, sparseSpec(shape, count, seed));
      const std::string truthText = test::slurp(dir / "ph/truth.yaml");
      const std::size_t at = truthText.find("betti: [");
      ASSERT_NE(at, std::string::npos);
      std::string truth = truthText.substr(at + 7, truthText.find(']', at) - at - 6);
      truth.erase(std::remove(truth.begin(), truth.end(), ' '), truth.end());
      const nlohmann::json free = test::run(dir, "free", "");
      const auto r = test::runXsect("run " + (dir / "ph/config.yaml").string() + " --out " + (dir / "target").string() +
                                    " --quiet --set reconstruction.topology=" + truth);
      ++configs;
      freeRight += free["betti"].dump() == nlohmann::json::parse(truth).dump();
      if (r.code != 0) {
        EXPECT_EQ(r.code, 2) << tag << r.err;  // refused, naming the key
        EXPECT_NE(r.err.find("reconstruction.topology"), std::string::npos) << r.err;
        failures += " " + tag;
        continue;
      }
      const nlohmann::json t = test::readJson(dir / "target/report.json");
      EXPECT_EQ(t["betti"], nlohmann::json::parse(truth)) << tag;
      expectMendsOnlyRemoveFeatures(t["topology"], tag);
      EXPECT_EQ(t["voxel_betti"], t["betti"]) << tag;  // one solid
      ++reached;
      fs::remove_all(dir);
    }
  std::cout << "topology control: truth reached on " << reached << " of " << configs << " (free: " << freeRight
            << "); refused:" << failures << "\n";
  // Measured: 16 of 16 (15 before cells were mended: genus-2, 30 planes, seed 3 refused). Seeds
  // 1-8 of bench/topology_family.py: 56 and 55 of 57 (methods 1, 2; refused: a torus whose only
  // two sections lie in no common cell, so that no join of a cell can make it one component).
  EXPECT_EQ(reached, configs) << "refused:" << failures;
  EXPECT_GT(reached, freeRight);
}

}  // namespace
}  // namespace xsect

namespace xsect {
namespace {

/// Real contour sets (../shared/data, skipped when absent): the mug of the contour-set literature
/// (5 planes of mixed orientations, genus 1) and OReX's Elephant (truth (1, 0, 0)). `simplest`
/// never gives a feature more than the method's own solid. The mug's truth is met by methods 1
/// and 2 (their solids: b1 = 9 and 7, gaps between the walls lifted from parallel planes, filled
/// by mends); on the Elephant (b1 = 11 and 13: pinholes where lifts meet next to planes) at most
/// two tunnels are left (measured: 1 and 2), and the truth is met or refused naming the key.
TEST(TopologyControlRealData, MugMeetsItsTruthAndTheElephantLosesAllButAtMostTwoTunnels) {
  const fs::path data = fs::path(XSECT_SOURCE_DIR) / "../shared/data";
  struct RealSet {
    std::string name, input, truth;
    int most_tunnels_left;  ///< simplest
  };
  const std::vector<RealSet> sets{{"mug", "contour: " + (data / "contour/mug.contour").string(), "[1,1,0]", 1},
                                  {"elephant", "csl: " + (data / "orex/Elephant.csl").string(), "[1,0,0]", 2}};
  if (!fs::exists(data / "contour/mug.contour") || !fs::exists(data / "orex/Elephant.csl"))
    GTEST_SKIP() << "no ../shared/data";
  for (const RealSet& set : sets)
    for (const std::string method : {"nearest_plane", "section_voronoi"}) {
      const std::string name = set.name + " " + method;
      const fs::path dir = test::freshDir("topology-" + set.name);
      test::writeFile(dir / "config.yaml", "input:\n  " + set.input + "\nreconstruction:\n  method: " + method +
                                               "\noutput:\n  mesh: [ply]\n");
      const nlohmann::json free = runRing(dir, "free", "");
      const nlohmann::json simplest = runRing(dir, "simplest", "--set reconstruction.topology=simplest");
      for (int i = 0; i < 3; ++i) EXPECT_LE(simplest["betti"][i], free["betti"][i]) << name;
      EXPECT_EQ(simplest["voxel_betti"], simplest["betti"]) << name;
      EXPECT_EQ(simplest["topology"]["betti_after"], simplest["betti"]) << name;
      EXPECT_EQ(simplest["betti"][0], 1) << name;
      EXPECT_LE(simplest["betti"][1], set.most_tunnels_left) << name;
      expectMendsOnlyRemoveFeatures(simplest["topology"], name);
      const auto r = test::runXsect("run " + (dir / "config.yaml").string() + " --out " + (dir / "target").string() +
                                    " --quiet --set reconstruction.topology=" + set.truth);
      if (set.name == "mug") ASSERT_EQ(r.code, 0) << name << r.err;
      if (r.code == 0)
        EXPECT_EQ(test::readJson(dir / "target/report.json")["betti"], nlohmann::json::parse(set.truth)) << name;
      else
        EXPECT_TRUE(r.code == 2 && r.err.find("reconstruction.topology") != std::string::npos) << name << r.err;
      fs::remove_all(dir);
    }
}

}  // namespace
}  // namespace xsect
