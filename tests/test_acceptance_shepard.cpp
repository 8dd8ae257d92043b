// Acceptance of the smooth surface (thesis ch. 1 §1.1, Shepard's interpolant) through the command
// line: the zero set passes through the section contours, the level set is written, the smooth
// solid joins the sections as the method's graph does, and on densely sliced phantoms it has the
// right Betti numbers and is closer to the truth than method 1.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>

#include "cli.h"
#include "phantom_runs.h"
#include "geometry/evaluation/mesh_distance.h"
#include "geometry/core/polygon.h"
#include "io/level_set_file.h"
#include "io/mesh_io.h"

namespace fs = std::filesystem;
using json = nlohmann::json;
using namespace xsect;

namespace {

using test::eval;
using test::phantom;
using test::readJson;
using test::run;
using test::sectionsOf;

const char* kTorusMultiaxial =
    "seed: 2\nshape: {kind: torus, params: {major_radius: 12, minor_radius: 4}}\n"
    "pattern: {kind: multiaxial, count: 12}\nimage: {pixel_mm: 0.1}\n"
    "config: {reconstruction: {voxel_size_mm: 0.25}}\n";

}  // namespace

TEST(AcceptanceShepard, ZeroSetPassesThroughTheContoursWithinHalfAVoxel) {
  const fs::path dir = phantom("shepard-conformity", kTorusMultiaxial);
  // Without the conformal cut: the surface as OpenVDB meshes the level set, nothing snapped.
  run(dir, "res", "--set smoothing.method=shepard --set reconstruction.conformal_mesh=false");
  const TriangleMesh mesh = readMesh((dir / "res/mesh.ply").string());
  const MeshDistance distance(mesh);
  const auto planes = sectionsOf(dir / "ph/config.yaml");
  const double voxel = 0.25;
  std::vector<Vec3> samples;
  for (const auto& p : planes)
    for (const Vec2& a : contourSamples(p.sections, 0.2 * voxel)) samples.push_back(p.plane.toWorld(a));
  ASSERT_GT(samples.size(), 5000u);
  const std::vector<double> d = distance.distances(samples);
  double worst = 0, sum = 0;
  for (const double v : d) {
    worst = std::max(worst, v);
    sum += v;
  }
  // The mesh is OpenVDB's polygonisation of the level set: it cuts the creases where the surface
  // crosses two planes by a little more.
  EXPECT_LE(worst, 0.6 * voxel) << "mean " << sum / d.size();
  EXPECT_LE(sum / d.size(), 0.15 * voxel);

  // The level set written beside the mesh (a narrow band of signed distance, negative inside): its
  // zero set, trilinear between voxel centres, within half a voxel of every contour sample.
  const NarrowBandLevelSet ls = readLevelSetVdb((dir / "res/level_set.vdb").string());
  EXPECT_GT(ls.coords.size(), 10000u);
  EXPECT_NEAR(ls.background, 3 * voxel, 1e-6);
  std::map<std::array<int, 3>, float> band;
  for (std::size_t q = 0; q < ls.coords.size(); ++q) band[ls.coords[q]] = ls.values[q];
  double worstLs = 0;
  int over = 0;
  for (const Vec3& x : samples) {
    const Vec3 g = (x - ls.grid.origin) / ls.grid.voxel;
    const int i = int(std::floor(g.x())), j = int(std::floor(g.y())), k = int(std::floor(g.z()));
    double v = 0;
    for (int c = 0; c < 8; ++c) {
      const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
      const auto it = band.find({i + di, j + dj, k + dk});
      ASSERT_NE(it, band.end()) << "a contour point outside the narrow band";
      v += (di ? g.x() - i : 1 - (g.x() - i)) * (dj ? g.y() - j : 1 - (g.y() - j)) *
           (dk ? g.z() - k : 1 - (g.z() - k)) * it->second;
    }
    worstLs = std::max(worstLs, std::abs(v));
    over += std::abs(v) > 0.5 * voxel;
  }

  // Every sample within half a voxel. Without the contour pinning (contour_pinning.h), 1612 of
  // the 86,648 samples (at the tube's top and bottom, beside the outermost z-planes) read up to
  // 0.67 voxel off.
  EXPECT_EQ(over, 0) << "worst " << worstLs;
  EXPECT_LE(worstLs, 0.5 * voxel);
  const json rep = readJson(dir / "res/report.json");
  EXPECT_GT(rep["smoothing"]["contour_pinning"]["voxels_pinned"].get<int>(), 0);
  EXPECT_GT(rep["smoothing"]["contour_pinning"]["worst_before_mm"].get<double>(), 0.5 * voxel);
  EXPECT_EQ(rep["smoothing"]["surface_from"], "shepard");
  EXPECT_EQ(rep["betti"], json::array({1, 1, 0}));
  EXPECT_TRUE(rep["watertight"]);
  // The torus tube's core (major radius 12 in the z = 0 plane) is deep inside; far away is outside.
  EXPECT_LT(levelSetValueAt((dir / "res/level_set.vdb").string(), Vec3(12, 0, 0)), 0.0f);
  EXPECT_GT(levelSetValueAt((dir / "res/level_set.vdb").string(), Vec3(0, 0, 0)), 0.0f);
  // Shepard's solid joins the sections as the method's graph G does.
  EXPECT_TRUE(rep["smoothing"]["shepard_connectivity"]["same_partition_as_graph"]);
  EXPECT_TRUE(fs::exists(dir / "res/mesh_unsmoothed.ply"));
  // Its grid reaches the end planes, beyond method 1's, on the same voxel lattice (the per-cell
  // comparison with the method's solid reads the same voxel centres in both).
  for (int a = 0; a < 3; ++a) {
    const double shift = (rep["reconstruction"]["grid_origin_mm"][a].get<double>() -
                          rep["smoothing"]["grid_origin_mm"][a].get<double>()) / voxel;
    EXPECT_GE(shift, 1.0) << "axis " << a;
    EXPECT_NEAR(shift, std::round(shift), 1e-6) << "axis " << a;
  }
  fs::remove_all(dir);
}

// Dense slicing: each phantom's Betti numbers, and a mean distance to the truth at most half of
// method 1's on the same input, with the default exponent (p = 1, the thesis' "natural choice":
// between two parallel planes f is the linear interpolation of their distance functions).
// On 120 random planes the ratio is not met: the cells are small polyhedra with many facets whose
// votes (for p = 1) do not fade with distance; Shepard's surface is still closer to the truth than
// method 1's (0.89 of its distance; the level-set smoothing reaches 0.74). That case also exercises
// the per-cell rule's refinement: on the grid Shepard's solid joins the sections of 4 cells
// (at most 2.4 voxels deep) differently from G while method 1's does not; on finer lattices around
// them f joins them as G does, so Shepard's surface is kept (cell_refinement.h).
struct DenseCase {
  const char* name;
  std::string spec;
  double max_ratio;
  const char* surface_from;
};

const char* kGenus2Dense =
    "shape:\n  kind: genus2\n  params: {disk_radius: 20, hole_radius: 5, hole_offset: 8, "
    "offset_radius: 2.5}\n  rotation_deg: [30, 0, 15]\nimage: {pixel_mm: 0.2}\n"
    "config: {reconstruction: {voxel_size_mm: 0.3}}\n";

TEST(AcceptanceShepard, DenselySlicedPhantomsHaveTheirBettiNumbersAndHalveMethod1sDistance) {
  const std::vector<DenseCase> cases = {
      {"sphere-parallel",
       "seed: 1\nshape: {kind: sphere, params: {radius: 10}}\npattern: {kind: parallel, count: 16}\n"
       "image: {pixel_mm: 0.1}\nconfig: {reconstruction: {voxel_size_mm: 0.25}}\n",
       0.5, "shepard"},
      {"torus-multiaxial", kTorusMultiaxial, 0.5, "shepard"},
      {"genus2-parallel", std::string("seed: 4\npattern: {kind: parallel, count: 40}\n") + kGenus2Dense, 0.5,
       "shepard"},
      {"genus2-random", std::string("seed: 4\npattern: {kind: random, count: 120}\n") + kGenus2Dense, 1.0,
       "shepard"},
  };
  for (const DenseCase& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path dir = phantom(std::string("shepard-") + c.name, c.spec);
    run(dir, "m1", "");
    run(dir, "sh", "--set smoothing.method=shepard");
    const json e1 = eval(dir, "m1"), es = eval(dir, "sh");
    EXPECT_EQ(es["betti"], es["truth_betti"]);
    EXPECT_TRUE(es["watertight"]);
    const double r = es["mean_distance_mm"].get<double>() / e1["mean_distance_mm"].get<double>();
    EXPECT_LE(r, c.max_ratio) << "Shepard " << es["mean_distance_mm"] << " mm, method 1 "
                              << e1["mean_distance_mm"] << " mm";
    const json rep = readJson(dir / "sh/report.json");
    EXPECT_EQ(rep["smoothing"]["exponent"], 1.0);
    EXPECT_EQ(rep["smoothing"]["surface_from"], c.surface_from);
    EXPECT_TRUE(rep["smoothing"]["connectivity"]["same_partition_as_graph"]);
    // The cells re-decided on finer lattices: each now differs from the graph in no more pairs
    // than method 1's solid does there (on random planes there are some; without the refinement
    // Shepard's surface would be replaced by the level-set smoothing).
    const json& refined = rep["smoothing"]["shepard_refined_cells"];
    if (std::string(c.name) == "genus2-random") EXPECT_GT(refined.size(), 0u);
    for (const json& cell : refined) {
      EXPECT_TRUE(cell["accepted"]) << cell;
      EXPECT_GE(cell["refinement"].get<int>(), 2) << cell;
      EXPECT_GE(cell["refined_pairs_differing"].get<int>(), 0) << cell;
      EXPECT_LE(cell["refined_pairs_differing"].get<int>(), cell["method_pairs_differing"].get<int>()) << cell;
      EXPECT_GT(cell["pairs_differing"].get<int>(), cell["method_pairs_differing"].get<int>()) << cell;
    }
    fs::remove_all(dir);
  }
}

TEST(AcceptanceShepard, RejectsInvalidSmoothingSettings) {
  const fs::path dir = phantom("shepard-bad",
                               "seed: 1\nshape: {kind: sphere, params: {radius: 5}}\n"
                               "pattern: {kind: parallel, count: 4}\nimage: {pixel_mm: 0.5}\n");
  for (const std::string bad : {"smoothing.method=spline", "smoothing.exponent=-1",
                                "smoothing.cap_mm=0", "smoothing.adaptivity=1.5",
                                "smoothing.iterations=2.5", "smoothing.keep_connectivity=maybe"}) {
    const auto r = test::runXsect("run " + (dir / "ph/config.yaml").string() + " --out " +
                                  (dir / "bad").string() + " --quiet --set " + bad);
    EXPECT_EQ(r.code, 2) << bad;
    EXPECT_NE(r.err.find(bad.substr(0, bad.find('='))), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "bad")) << bad;
  }
  fs::remove_all(dir);
}

// Thesis ch. 2 on the sparse vessel tree: method 2's graph joins all the sections in one tree,
// while Shepard's interpolant (like method 1) leaves the branches apart. The report says so, and
// by default the surface written is the level-set smoothing of R', which keeps the tree whole.
TEST(AcceptanceShepard, FallsBackToALevelSetSmoothingThatKeepsMethod2sConnectivity) {
  const fs::path dir = test::freshDir("shepard-tree");
  auto r = test::runXsect("phantom " + std::string(XSECT_SOURCE_DIR) +
                          "/configs/phantoms/vessel-tree-sparse.yaml --out " + (dir / "ph").string() +
                          " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string m2 = "--set reconstruction.method=section_voronoi --set smoothing.method=shepard ";
  run(dir, "kept", m2);
  run(dir, "raw", m2 + "--set smoothing.keep_connectivity=false");
  const json kept = readJson(dir / "kept/report.json"), raw = readJson(dir / "raw/report.json");
  EXPECT_FALSE(kept["smoothing"]["shepard_keeps_connectivity"]);
  EXPECT_GT(kept["smoothing"]["shepard_connectivity"]["pairs_joined_by_graph_only"].get<int>(), 0);
  EXPECT_TRUE(kept["smoothing"]["fell_back_to_level_set"]);
  EXPECT_EQ(kept["smoothing"]["surface_from"], "level_set");
  EXPECT_GT(kept["smoothing"]["level_set_iterations"].get<int>(), 0);
  EXPECT_TRUE(kept["smoothing"]["connectivity"]["same_partition_as_graph"]);
  // Cell by cell: the method's solid and the fallback agree with G' in every cell; Shepard's does
  // not (with p = 1 it misses the thin sections beside all 11 cells, which are then unresolved;
  // with p = 2 it resolves one and splits sections there that the graph joins).
  EXPECT_EQ(kept["graph"]["per_cell"]["cells_compared"].get<int>(), 11);
  EXPECT_EQ(kept["graph"]["per_cell"]["cells_differing"].get<int>(), 0);
  const json& sc = kept["smoothing"]["shepard_connectivity"]["per_cell"];
  EXPECT_LT(sc["cells_compared"].get<int>() - sc["cells_differing"].get<int>(), 11);
  EXPECT_GT(kept["smoothing"]["connectivity"]["per_cell"]["cells_compared"].get<int>(), 5);
  EXPECT_EQ(kept["smoothing"]["connectivity"]["per_cell"]["cells_differing"].get<int>(), 0);
  EXPECT_EQ(kept["betti"], json::array({1, 0, 0}));
  EXPECT_TRUE(kept["watertight"]);
  // Without the fallback the Shepard surface is written, its pieces apart, and flagged.
  EXPECT_EQ(raw["smoothing"]["surface_from"], "shepard");
  EXPECT_FALSE(raw["smoothing"]["connectivity"]["same_partition_as_graph"]);
  EXPECT_GT(raw["betti"][0].get<int>(), 1);
  bool warned = false;
  for (const auto& w : raw["warnings"]) warned = warned || w.get<std::string>().find("Shepard") != std::string::npos;
  EXPECT_TRUE(warned);
  // Asked for directly, the level-set smoothing holds the surface on the section contours too.
  run(dir, "ls", "--set reconstruction.method=section_voronoi --set smoothing.method=level_set");
  const json ls = readJson(dir / "ls/report.json");
  EXPECT_EQ(ls["smoothing"]["surface_from"], "level_set");
  EXPECT_TRUE(ls["smoothing"]["shepard_connectivity"].is_null());
  EXPECT_EQ(ls["betti"], json::array({1, 0, 0}));
  EXPECT_TRUE(fs::exists(dir / "ls/level_set.vdb"));
  fs::remove_all(dir);
}
