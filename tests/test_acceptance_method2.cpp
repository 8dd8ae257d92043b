// Acceptance of method 2 through the command line (phantom -> run -> eval): a thin vessel tree cut
// by sparse planes with planes passing just beside it (thesis ch. 2 §1, Fig. 2.1-2.2: method 1
// splits it, method 2 keeps it whole, and each graph groups the sections as its voxel solid does),
// and the phantom families of method 1 (phantom_families.h) within Thm 20's bound.
#include <gtest/gtest.h>

#include <sstream>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "phantom_families.h"

namespace fs = std::filesystem;
using json = nlohmann::json;
using namespace xsect;
using namespace xsect::test::families;

namespace {

json runReport(const fs::path& config, const fs::path& out, const std::string& sets) {
  const auto r = test::runXsect("run " + config.string() + " --out " + out.string() + " --quiet " + sets);
  EXPECT_EQ(r.code, 0) << r.err;
  return json::parse(std::ifstream(out / "report.json"));
}

}  // namespace

TEST(AcceptanceMethod2, SparseVesselTreeWithPlanesBesideIt) {
  // configs/phantoms/vessel-tree-sparse.yaml: a trunk (radius 0.6 mm) and two branches at 20
  // degrees, cut by planes 2.4 mm apart (4 trunk radii); two empty planes run along the tree
  // 0.4 mm beside the trunk's surface. Their Voronoi cells take the middle of every gap from
  // method 1; method 2's lifts never reach them.
  const fs::path dir = test::freshDir("vessel-m2");
  fs::copy_file(fs::path(XSECT_SOURCE_DIR) / "configs/phantoms/vessel-tree-sparse.yaml", dir / "spec.yaml");
  const auto r = test::runXsect("phantom " + (dir / "spec.yaml").string() + " --out " + (dir / "ph").string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const json m1 = runReport(dir / "ph/config.yaml", dir / "m1", "");
  const json m2 = runReport(dir / "ph/config.yaml", dir / "m2", "--set reconstruction.method=section_voronoi");
  EXPECT_GT(m1["betti"][0].get<int>(), 1) << "method 1 should split the tree at the planes beside it";
  EXPECT_EQ(m2["betti"], json::array({1, 0, 0})) << "method 2 should keep it in one piece";
  for (const json* m : {&m1, &m2}) {
    EXPECT_TRUE((*m)["graph"]["same_partition_as_voxels"].get<bool>());
    EXPECT_EQ((*m)["graph"]["components"], (*m)["betti"][0]);
    EXPECT_EQ((*m)["voxel_betti"], (*m)["betti"]);
  }
  EXPECT_TRUE(m2["graph"]["g_subset_of_g_prime"].get<bool>());
  EXPECT_GT(m2["graph"]["edges_g_prime"].get<int>(), m1["graph"]["edges_g"].get<int>() / 2);
  fs::remove_all(dir);
}

TEST(AcceptanceMethod2, SmoothVesselTreeMeetingWeakDensityKeepsTopologyWithinTheLiftBound) {
  // Branches at 35 degrees with 6 mm fillets (reach_e ~2.5 mm, reach_i ~0.46 mm), planes 1.2 mm
  // apart (2 trunk radii): every lift is shorter than reach_e (Weak Density, checked below), and
  // the branches cross the planes steeply enough that the boundary's projection within a Voronoi
  // cell moves by about 0.6 tan 35° = 0.42 mm < reach_i (Weak Transversality, by construction).
  // Theorems 19-20: the right topology, and d_H(O, R') <= the longest lift.
  const fs::path dir = test::freshDir("vessel-wd");
  std::string positions;
  for (int i = 0; i < 22; ++i) positions += (i ? ", " : "") + std::to_string(0.5 + 1.2 * i);
  test::writeFile(dir / "spec.yaml", "seed: 11\nshape:\n  kind: vessel_tree\n  params: {length: 14, radius: 0.6,"
                  " levels: 1, branch_angle_deg: 35, blend_mm: 6, seed: 1}\npattern:\n  kind: parallel\n"
                  "  direction: [0, 0, 1]\n  positions_mm: [" + positions + "]\nimage: {pixel_mm: 0.06}\n"
                  "config: {reconstruction: {voxel_size_mm: 0.12, end_margin_mm: 0.6,"
                  " method: section_voronoi}}\n");
  auto r = test::runXsect("phantom " + (dir / "spec.yaml").string() + " --out " + (dir / "ph").string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const json rep = runReport(dir / "ph/config.yaml", dir / "m2", "");
  r = test::runXsect("eval --mesh " + (dir / "m2/mesh.ply").string() + " --truth " + (dir / "ph/truth.yaml").string() +
                     " --voxel 0.04 --json " + (dir / "eval.json").string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const json ev = json::parse(std::ifstream(dir / "eval.json"));
  const YAML::Node truth = YAML::LoadFile((dir / "ph/truth.yaml").string());
  const double lift = rep["reconstruction"]["max_lift_mm"];
  ASSERT_LT(lift, truth["reach_exterior_mm"].as<double>()) << "Weak Density does not hold";
  EXPECT_EQ(rep["betti"], json::array({1, 0, 0}));
  EXPECT_EQ(ev["betti"], json::array({1, 0, 0}));
  EXPECT_LE(ev["hausdorff_mm"].get<double>(), lift + 0.12);
  // The headline eval prints, with or without --json: the same numbers, the topology judged.
  std::ostringstream hausdorff;
  hausdorff.setf(std::ios::fixed);
  hausdorff.precision(3);
  hausdorff << ev["hausdorff_mm"].get<double>();
  EXPECT_NE(r.out.find("topology: 1 0 0 (truth 1 0 0: right), watertight\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Hausdorff " + hausdorff.str() + " mm"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("json: " + (dir / "eval.json").string()), std::string::npos) << r.out;
  r = test::runXsect("eval --mesh " + (dir / "m2/mesh.ply").string() + " --truth " + (dir / "ph/truth.yaml").string() +
                     " --voxel 0.04 --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("Hausdorff " + hausdorff.str() + " mm"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("json:"), std::string::npos) << r.out;
  fs::remove_all(dir);
}

TEST(AcceptanceMethod2, Multiaxial) {
  for (const auto& sh : shapes()) {
    Case c{sh.name + " multiaxial, method 2", sh.yaml,
           "{kind: multiaxial, count: " + std::to_string(sh.multiaxial) + "}", 0.3};
    c.method = "section_voronoi";
    runCase(c);
  }
}

TEST(AcceptanceMethod2, RandomPlanes) {
  Case c{"torus random, method 2", shapes()[1].yaml, "{kind: random, count: 140}", 0.3};
  c.method = "section_voronoi";
  runCase(c);
}
