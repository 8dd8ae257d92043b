// Issue 14 through the command line: the mesh written is the solid report.json states (smoothing
// keeps cavities: the hollow sphere over several seeds and a tilted pattern), a grid too coarse for
// the sections is refused or warned about, and an empty result is an error, never exit 0.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "phantom_runs.h"

namespace fs = std::filesystem;
using json = nlohmann::json;
using namespace xsect;
using test::eval;
using test::phantom;
using test::readJson;
using test::run;

namespace {

std::string hollowSphere(int seed, const char* rotation) {
  return "seed: " + std::to_string(seed) +
         "\nshape: {kind: hollow_sphere, params: {outer_radius: 12, inner_radius: 7}, rotation_deg: " + rotation +
         "}\npattern: {kind: multiaxial, count: 12}\nimage: {pixel_mm: 0.25}\n"
         "config: {reconstruction: {voxel_size_mm: 0.4}}\n";
}

/// A small sphere phantom (radius 5 mm) whose configuration keeps the automatic voxel size.
fs::path smallSphere(const std::string& tag) {
  return phantom(tag, "seed: 1\nshape: {kind: sphere, params: {radius: 5}}\npattern: {kind: multiaxial, count: 4}\n"
                      "image: {pixel_mm: 0.2}\n");
}

/// A thin ellipsoid (40 x 6 x 6 mm) cut across its length by 10 planes: sections at most 6 mm wide.
fs::path thinEllipsoid(const std::string& tag) {
  return phantom(tag, "seed: 1\nshape: {kind: ellipsoid, params: {a: 20, b: 3, c: 3}}\n"
                      "pattern: {kind: parallel, count: 10, direction: [1, 0, 0]}\nimage: {pixel_mm: 0.2}\n");
}

/// `xsect run` of the phantom in dir into dir/out, quiet, with the overrides `sets`.
test::CliResult runPhantom(const fs::path& dir, const std::string& sets) {
  return test::runXsect("run " + (dir / "ph/config.yaml").string() + " --out " + (dir / "out").string() + " --quiet " +
                        sets);
}

/// The run of the phantom in dir with `sets` exits with `code`, its message holds every `part`,
/// and no output folder is left; dir is removed.
void expectRefused(const fs::path& dir, const std::string& sets, int code, const std::vector<std::string>& parts) {
  const auto r = runPhantom(dir, sets);
  EXPECT_EQ(r.code, code) << r.err;
  for (const std::string& part : parts) EXPECT_NE(r.err.find(part), std::string::npos) << part << "\n" << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

}  // namespace

TEST(AcceptanceMeshIsSolid, HollowSphereKeepsItsCavityWithEverySmoothing) {
  // Seeds move the planes; the tilted pattern is the "other hollow shape" of the issue. (Seed 6,
  // the spec of configs/phantoms/hollow-sphere-multiaxial.yaml, is in the topology matrix.)
  const std::vector<std::pair<int, const char*>> cases = {{11, "[0, 0, 0]"}, {3, "[20, 35, 10]"}};
  for (const auto& [seed, rotation] : cases) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " rotation " + rotation);
    const fs::path dir = phantom("hollow", hollowSphere(seed, rotation));
    run(dir, "m1", "");
    const double method1 = eval(dir, "m1")["mean_distance_mm"].get<double>();
    for (const std::string sets : {"--set smoothing.method=shepard --set smoothing.exponent=1",
                                   "--set smoothing.method=shepard --set smoothing.exponent=2",
                                   "--set smoothing.method=shepard --set smoothing.exponent=4",
                                   "--set smoothing.method=level_set"}) {
      SCOPED_TRACE(sets);
      const json rep = run(dir, "s", sets);
      const json e = eval(dir, "s");
      EXPECT_EQ(e["betti"], json::array({1, 0, 1}));
      EXPECT_EQ(rep["betti"], e["betti"]);
      EXPECT_EQ(rep["smoothing"]["voxel_betti"], e["betti"]);
      EXPECT_TRUE(e["watertight"].get<bool>());
      EXPECT_LT(e["mean_distance_mm"].get<double>(), method1);
      fs::remove_all(dir / "s");
    }
    fs::remove_all(dir);
  }
}

TEST(AcceptanceMeshIsSolid, AutomaticVoxelSizeIsTheDefaultAndReported) {
  const fs::path dir = smallSphere("auto-voxel");
  test::writeFile(dir / "only-input.yaml", "input:\n  slices: " + (dir / "ph/slices.yaml").string() + "\n");
  const auto r = test::runXsect("run " + (dir / "only-input.yaml").string() + " --out " + (dir / "out").string() +
                                " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const json rep = readJson(dir / "out/report.json");
  const json& v = rep["reconstruction"]["voxel_size"];
  EXPECT_TRUE(v["auto"].get<bool>());
  EXPECT_EQ(v["voxel_size_mm"], rep["reconstruction"]["voxel_size_mm"]);
  // The rule: at most a hundredth of the bounds' diagonal, at least half a pixel (0.2 mm).
  EXPECT_LE(v["voxel_size_mm"].get<double>(), v["bounds_diagonal_mm"].get<double>() / 100 * 1.05);
  EXPECT_GE(v["voxel_size_mm"].get<double>(), 0.1 * 0.95);
  EXPECT_EQ(v["sections_narrower_than_two_voxels"], 0);
  EXPECT_EQ(rep["betti"], json::array({1, 0, 0}));
  fs::remove_all(dir);
}

TEST(AcceptanceMeshIsSolid, CoarseExplicitVoxelSizeWarnsLoudly) {
  const fs::path dir = thinEllipsoid("coarse");
  // Voxels of 3.2 mm: every section is narrower than two voxels; the solid is not empty yet (it is
  // from 3.8 mm on).
  const auto r = runPhantom(dir, "--set reconstruction.voxel_size_mm=3.2");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("WARNING: reconstruction.voxel_size_mm = 3.2 mm is too coarse"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Use reconstruction.voxel_size_mm: 1.3"), std::string::npos) << r.err;  // median width / 4
  EXPECT_NE(r.err.find("sections are narrower than two voxels"), std::string::npos) << r.err;
  const json rep = readJson(dir / "out/report.json");
  EXPECT_NE(rep["warnings"][0].get<std::string>().find("too coarse"), std::string::npos);
  EXPECT_GT(rep["reconstruction"]["voxel_size"]["sections_narrower_than_two_voxels"].get<int>(),
            rep["counts"]["sections"].get<int>() / 2);
  fs::remove_all(dir);
}

TEST(AcceptanceMeshIsSolid, AutomaticSizeForcedCoarseByTheBudgetIsAnInputError) {
  expectRefused(smallSphere("budget"), "--set reconstruction.voxel_budget=1000", 2,
                {"reconstruction.voxel_size_mm", "limited by reconstruction.voxel_budget = 1000",
                 "set reconstruction.voxel_size_mm: 2.4 (a quarter of the median width) and reconstruction.voxel_budget: "});
  // Method 2's grid has at least 12^3 voxels of margins: no size fits 1000.
  expectRefused(smallSphere("budget2"), "--set reconstruction.voxel_budget=1000 --set reconstruction.method=section_voronoi",
                2, {"reconstruction.voxel_size_mm: no voxel size fits a grid of 1000 voxels", "raise reconstruction.voxel_budget"});
}

TEST(AcceptanceMeshIsSolid, EmptyResultFromNonEmptySectionsIsAnError) {
  // 5 mm voxels: no voxel centre lies in the ellipsoid. The setting is the cause: exit 2 (issue 48:
  // an explicit size as an automatic one).
  expectRefused(thinEllipsoid("empty"), "--set reconstruction.voxel_size_mm=5", 2,
                {"the reconstructed solid is empty although the input has", "use a smaller reconstruction.voxel_size_mm"});
}

TEST(AcceptanceMeshIsSolid, ALabelTooSmallForTheGridIsAWarningNotAFailure) {
  // Label images: a disk of label 1 on 8 parallel slices, and a 2 x 2 pixel speck of label 2 on
  // one (0.4 mm, a stray value of a label map): the grid has no voxel of label 2.
  const fs::path dir = test::freshDir("small-label");
  fs::create_directories(dir / "images");
  std::string slices = "slices:\n";
  for (int k = 0; k < 8; ++k) {
    cv::Mat m = cv::Mat::zeros(120, 120, CV_8U);
    cv::circle(m, {60, 60}, 40, cv::Scalar(1), -1);
    if (k == 3) cv::rectangle(m, {10, 10}, {11, 11}, cv::Scalar(2), -1);
    const std::string name = "images/" + std::to_string(k) + ".png";
    ASSERT_TRUE(cv::imwrite((dir / name).string(), m));
    slices += "  - image: " + name + "\n    image_to_world:\n      - [0.2, 0, 0, -12]\n      - [0, 0.2, 0, -12]\n"
              "      - [0, 0, 0, " + std::to_string(k) + "]\n      - [0, 0, 0, 1]\n";
  }
  test::writeFile(dir / "slices.yaml", slices);
  test::writeFile(dir / "config.yaml", "input:\n  slices: slices.yaml\nsegmentation:\n  method: labels\n");
  const auto r = test::runXsect("run " + (dir / "config.yaml").string() + " --out " + (dir / "out").string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const json rep = readJson(dir / "out/report.json");
  EXPECT_NE(rep["warnings"].dump().find("label 2 has sections but no voxel"), std::string::npos) << rep["warnings"];
  ASSERT_EQ(rep["materials"].size(), 1u);
  EXPECT_EQ(rep["materials"][0]["label"], 1);
  EXPECT_EQ(rep["materials"][0]["betti"], rep["materials"][0]["voxel_betti"]);
  EXPECT_TRUE(fs::exists(dir / "out/mesh_label_1.ply"));
  EXPECT_FALSE(fs::exists(dir / "out/mesh_label_2.ply"));
  fs::remove_all(dir);
}
