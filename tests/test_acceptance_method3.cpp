// Method 3 (reconstruction.method: delaunay) end to end on phantoms whose planes and pixels share a
// grid: contours then cross other planes exactly at their vertices, and branching lattices meet
// traces exactly. Those crossings must be trace points bounding the cells on both sides (without
// them the gluing filed ground triangles on the wrong side of a plane and the hollow sphere's mesh
// had 544 open edges: `xsect run` refused it). Checked: the run writes its mesh, the mesh is
// closed with the truth's Betti numbers (a cavity: b2 = 1), and it lies within the slice gap of the
// analytic surface; with 11 and 13 planes per axis (planes off the pixel grid) the same. A fan of
// planes through the sections is refused (not general position).
// Thesis Fig. 1.11 (two planes, a C and the C turned by 180 degrees): one solid, whose mesh has the
// components of its tetrahedra (the pinch handling once cut it in two at the C's gap ends).
// Two spheres between tilted planes: two solids, R'' joining no two components of G''. The split
// torus's halves: the truth's Betti numbers once label images are smoothed before tracing.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "geometry/core/disjoint_sets.h"
#include "phantom_runs.h"

namespace fs = std::filesystem;
using json = nlohmann::json;
using namespace xsect;

namespace {

/// configs/phantoms/hollow-sphere-multiaxial.yaml (12 planes per axis, 0.25 mm pixels) with
/// `count` planes per axis and `pixel` mm pixels.
std::string hollowSphere(int count, double pixel) {
  return "seed: 6\nshape: {kind: hollow_sphere, params: {outer_radius: 12, inner_radius: 7}}\n"
         "pattern: {kind: multiaxial, count: " + std::to_string(count) + "}\nimage: {pixel_mm: " +
         std::to_string(pixel) + "}\nconfig: {reconstruction: {voxel_size_mm: 0.4}}\n";
}

/// Method 3 (into dir/m3, with `sets`) on the phantom `spec` rendered into a fresh folder `tag`:
/// the run writes its mesh, closed (no open edge, watertight). Returns the folder.
fs::path closedMethod3Run(const std::string& tag, const std::string& spec, const std::string& sets = "") {
  const fs::path dir = test::phantom(tag, spec);
  const json r = test::run(dir, "m3", "--set reconstruction.method=delaunay " + sets);
  EXPECT_TRUE(fs::exists(dir / "m3/mesh.ply"));
  EXPECT_EQ(r["reconstruction"]["delaunay"]["open_edges"], 0);
  EXPECT_EQ(r["watertight"], true);
  return dir;
}

/// Method 3 on a genus-2 phantom cut by random planes (`spec`): closed, with one outer surface.
/// Returns report.json.
json closedRandomPlanesRun(const std::string& tag, const std::string& spec) {
  const json r = test::readJson(closedMethod3Run(tag, spec, "--set reconstruction.end_margin_mm=1.0") / "m3/report.json");
  EXPECT_EQ(r["betti"][0], 1);
  return r;
}

}  // namespace

TEST(AcceptanceMethod3, HollowSphereOnAndOffThePixelGridIsClosedWithItsCavity) {
  for (const auto& [count, pixel] : {std::pair{12, 0.25}, std::pair{11, 0.25}, std::pair{13, 0.3}}) {
    const std::string tag = "m3-hollow-" + std::to_string(count);
    SCOPED_TRACE(tag);
    const fs::path dir = test::phantom(tag, hollowSphere(count, pixel));
    const json r = test::run(dir, "m3", "--set reconstruction.method=delaunay");
    ASSERT_TRUE(fs::exists(dir / "m3/mesh.ply"));
    const json& d = r["reconstruction"]["delaunay"];
    EXPECT_EQ(d["open_edges"], 0);
    EXPECT_EQ(r["betti"], json::array({1, 0, 1}));
    EXPECT_EQ(d["mesh_betti"], json::array({1, 0, 1}));
    const json e = test::eval(dir, "m3");
    // count planes per axis across 24 mm: a gap of 24 / count mm.
    EXPECT_LT(e["hausdorff_mm"].get<double>(), 24.0 / count);
    EXPECT_LT(e["mean_distance_mm"].get<double>(), 0.2);
    std::cerr << tag << ": betti " << r["betti"] << ", Hausdorff " << e["hausdorff_mm"] << " mm, mean "
              << e["mean_distance_mm"] << " mm\n";
  }
}

// Fig. 1.11: the C on z = 0 and the C turned by 180 degrees on z = 20 (configs/phantoms/
// fig-1-11-*.yaml, with coarser pixels). Between the gap ends, the two fans of triangles meet along
// one Delaunay edge from the inner contour to the outer one; keeping the wedges apart along it
// cut R'' into two meshes although its tetrahedra are one component. The data fit the twisted
// cylinder (1, 0, 0) and the notched torus (1, 1, 0) alike: either is right, two pieces is not.
TEST(AcceptanceMethod3, TwoTurnedCsAreOneSolid) {
  for (const char* shape : {"twisted_cylinder", "notched_torus"}) {
    SCOPED_TRACE(shape);
    const std::string notch = std::string(shape) == "notched_torus" ? ", notch: 1" : "";
    const fs::path dir = test::phantom(
        std::string("m3-fig-1-11-") + shape,
        std::string("seed: 10\nshape:\n  kind: ") + shape +
            "\n  params: {inner_radius: 6, outer_radius: 10, gap_deg: 60, height: 20, extension: 3" + notch +
            "}\npattern: {kind: parallel, direction: [0, 0, 1], positions_mm: [0, 20]}\n"
            "image: {pixel_mm: 0.2}\nconfig: {reconstruction: {voxel_size_mm: 0.5}}\n");
    const json r = test::run(dir, "m3", "--set reconstruction.method=delaunay");
    ASSERT_TRUE(fs::exists(dir / "m3/mesh.ply"));
    const json& d = r["reconstruction"]["delaunay"];
    EXPECT_EQ(d["open_edges"], 0);
    EXPECT_EQ(d["tetrahedra_components"], 1);
    EXPECT_EQ(r["betti"][0], 1);
    EXPECT_LE(r["betti"][1].get<int>(), 1);
    EXPECT_EQ(r["betti"][2], 0);
  }
}

// Two spheres between 30 planes tilted up to 5 degrees (configs/phantoms/two-spheres-parallel.yaml,
// and other seeds): where two planes cross between the spheres, sliver tetrahedra join contour edges
// of one sphere on a plane to contour edges of the other on the next plane across the cell's hull
// (688 of them, 16 mm long and 0.04 mm thick, at seed 7), and no external grounded simplex removes
// them: R'' was one solid with 17 tunnels. G'' never joins the two spheres' sections, and step 1
// removes every tetrahedron joining sections of two components of G'' (cell_complex.h,
// markUnjoined). Checked: two solids without tunnel, every connection R'' realises within one
// component of G'' (graph.json), the mesh within the slice gap of the truth.
TEST(AcceptanceMethod3, TwoSpheresBetweenTiltedPlanesStayTwoSolids) {
  for (const int seed : {7, 1, 2, 3}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const fs::path dir = closedMethod3Run(
        "m3-two-spheres-" + std::to_string(seed),
        "seed: " + std::to_string(seed) +
            "\nshape: {kind: two_spheres, params: {radius: 6, separation: 16}}\n"
            "pattern: {kind: parallel, count: 30, direction: [0, 1, 0], tilt_deg: 5}\n"
            "image: {pixel_mm: 0.2}\ndegradations: {noise_sigma: 10, blur_sigma_px: 1}\n"
            "config: {reconstruction: {voxel_size_mm: 0.3}}\n");
    EXPECT_EQ(test::readJson(dir / "m3/report.json")["betti"], json::array({2, 0, 0}));
    // What graph.json says agrees: the components of G'' (edges of method "delaunay") hold every
    // connection R'' realises (the spheres' sections never touch, so no trace joins them).
    const json g = test::readJson(dir / "m3/graph.json");
    DisjointSets parts(g["nodes"].size());
    for (const json& e : g["edges"])
      if (e["method"] == "delaunay") parts.unite(e["a"].get<std::size_t>(), e["b"].get<std::size_t>());
    int across = 0;
    for (const json& e : g["delaunay_connections"])
      across += parts.find(e["a"].get<std::size_t>()) != parts.find(e["b"].get<std::size_t>());
    EXPECT_EQ(across, 0) << "R'' joins sections that G'' does not connect";
    EXPECT_GT(g["delaunay_connections"].size(), 0u);
    // Measured 0.23-0.94 mm on these seeds (4.0 mm with the slivers). The 30 planes cross the
    // spheres' 12 mm at random heights (seed 7: gaps up to 1.5 mm), tilted up to 5 degrees.
    const json e = test::eval(dir, "m3");
    std::cout << "seed " << seed << ": Hausdorff " << e["hausdorff_mm"] << " mm, mean " << e["mean_distance_mm"] << " mm\n";
    EXPECT_LT(e["hausdorff_mm"].get<double>(), 1.5);
  }
}

// The split torus (configs/phantoms/split-torus-multiaxial.yaml: two C-shaped halves, labels 1 and
// 2, three stacks of 10 planes) at four rotations. Label images are not anti-aliased; traced as
// they are, the contours are pixel staircases and R'' joined the steps of neighbouring planes into
// tunnels (Betti (1, 5, 0) to (1, 9, 0), or (3, 1, 0), against (1, 1, 0); each half (1, 2, 0) or
// (1, 3, 0) against (1, 0, 0)). `xsect phantom` now writes segmentation.sigma_px: 1.5 for label
// phantoms: the union and each material have the truth's Betti numbers, and the mesh lies within
// the slice gap (about 3 mm) of the torus.
TEST(AcceptanceMethod3, SplitTorusHalvesHaveTheTruthsTopology) {
  const char* rotations[] = {"20, 10, 0", "0, 35, 15", "45, 0, 30", "70, 20, 40"};
  for (int k = 0; k < 4; ++k) {
    const std::string rotation = rotations[k];
    SCOPED_TRACE(rotation);
    const fs::path dir = closedMethod3Run(
        "m3-split-torus-" + std::to_string(k),
        "seed: 3\nshape:\n  kind: torus\n  params: {major_radius: 12, minor_radius: 4}\n  rotation_deg: [" +
            rotation + "]\n  label_split: {normal: [1, 0, 0]}\npattern: {kind: multiaxial, count: 10}\n"
            "image: {pixel_mm: 0.25}\nconfig: {reconstruction: {voxel_size_mm: 0.4}}\n");
    const json r = test::readJson(dir / "m3/report.json");
    EXPECT_EQ(r["betti"], json::array({1, 1, 0}));
    ASSERT_EQ(r["materials"].size(), 2u);
    for (const json& m : r["materials"]) EXPECT_EQ(m["betti"], json::array({1, 0, 0})) << "label " << m["label"];
    const json e = test::eval(dir, "m3");
    std::cout << rotation << ": Hausdorff " << e["hausdorff_mm"] << " mm\n";
    EXPECT_LT(e["hausdorff_mm"].get<double>(), 3.0);
  }
}

// Method 3 after enforced conformity (issue 5's edits: polygons sharing their consensus
// endpoints on each common line, thin rhombi where two traces disagreed), on the torus cut by
// three stacks of 10 planes with tracking error (σ = 1 mm, 1°). The edits leave section-vertices
// 1e-15 to 1e-12 mm apart, rhombi shorter than the sampling across a plane, and needles the weld
// collapses; before they were handled, 6 of these 8 seeds failed closed (open edges, or a mesh
// short of the tetrahedra's components: seeds 4 and 8 closed). Measured now: 7 of 8 glue ∂R''
// closed; seed 2 leaves five open edges on one plane (a pentagon where faces of two cells nearly
// parallel to the plane meet it, not consistently oriented) and its mesh is then the
// voxelisation of R'' (mesh_stage.h), with a warning: every seed runs (it used to exit 1, nothing
// written), and every written mesh has the Betti numbers report.json states, as `xsect eval`
// measures them on the file. Seed 2 is the one input known to take that path: the test requires
// one seed to take it, so that the path stays tested (should seed 2 glue one day, another input
// must be found). Betti numbers are not compared with the truth: with the consensus of jittered
// sections R'' has b1 of 3 to 10 (truth 1; 12 to 21 with the tunnels within cells kept).
TEST(AcceptanceMethod3, EnforcedConformityOfJitteredSectionsGivesAClosedMesh) {
  int glued = 0;
  for (int seed = 1; seed <= 8; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const fs::path dir = test::phantom("m3-enforced-" + std::to_string(seed), test::torusSpec(seed, true));
    const json rep = test::run(dir, "m3", "--set reconstruction.method=delaunay --set conformity.enforce=true");
    const json& d = rep["reconstruction"]["delaunay"];
    std::cout << "seed " << seed << ": betti " << rep["betti"] << ", mesh from " << d["mesh_source"] << ", open edges "
              << d["open_edges"] << ", welded " << d["welded_vertices"] << ", rings dropped "
              << d["rings_below_spacing_dropped"] << "\n";
    EXPECT_EQ(rep["watertight"], true);
    EXPECT_EQ(test::eval(dir, "m3")["betti"], rep["betti"]);  // the file carries the reported topology
    // One solid (issue 49): the voxels have the mesh's Betti numbers whatever the mesh's source.
    EXPECT_EQ(d["voxel_betti"], rep["betti"]);
    EXPECT_EQ(rep["voxel_betti"], rep["betti"]);
    glued += d["open_edges"] == 0;
    if (d["mesh_source"] == "boundary") {
      EXPECT_EQ(d["open_edges"], 0);
      EXPECT_EQ(d["mesh_betti"], rep["betti"]);
      EXPECT_EQ(rep["conformity"]["conformal_by_construction"], true);
    } else {
      ASSERT_EQ(d["mesh_source"], "voxels");
      EXPECT_EQ(rep["conformity"]["conformal_by_construction"], false);
      // Open edges, or a boundary whose topology no voxel set on the grid has: said so.
      const std::string why = d["open_edges"].get<int>() > 0 ? "could not be glued closed" : "is thinner than the voxel";
      bool warned = false;
      for (const json& w : rep["warnings"]) warned |= w.get<std::string>().find(why) != std::string::npos;
      EXPECT_TRUE(warned) << rep["warnings"];
    }
  }
  EXPECT_GE(glued, 7);
  EXPECT_GE(8 - glued, 1) << "no seed exercised the mesh from voxels of an open boundary any more";
}

// Issue 22's acceptance on sparse planes (bench/sparse_comparison.py puts methods 1, 2 and 3 side
// by side on 29 configurations, seeds 1-4; method 3 has the truth's topology on 20, method 1 on
// 15, method 2 on 14): the torus cut by 6 and 9 random planes and the genus-2 solid by 30 and 40,
// seeds 1-8 (5-8 are not the comparison's, on which the cutting of cell tunnels was developed).
// Method 3 has the truth's Betti numbers on more of them than methods 1 and 2. Measured: seeds
// 1-4, method 3 on 11 of 16, method 1 on 6, method 2 on 4 (method 3 with
// `reconstruction.cell_tunnels: keep`, the thesis' D3 as it is, on 5); seeds 5-8, 7 of 16 each
// (method 3 refuses the torus at 6 planes, seed 6: one plane holds sections; keep: 4; the cutting
// took the torus' true hole, lying inside one cell, at 6 and 9 planes, seed 5, and an extra tunnel
// at five others); together 18 of 32, 13 and 11. It takes 85-195 s (clean CI runs).
// One solid (issue 49): on 14 of the 32 no voxel set on the grid (centres or cubes, the voxel
// halved up to twice) has the Betti numbers of the boundary of R'', and the run writes the voxels'
// solid (mesh, labels.nrrd and report agree): R'' has the truth's topology on 18, the written
// solid on 13. The claim is about R''; the written count is printed beside it.
TEST(AcceptanceMethod3, SparsePlanesGiveTheTruthsTopologyMoreOftenThanMethods1And2) {
  const auto withLine = [](std::string text, const std::string& key, const std::string& line) {
    const std::size_t at = text.find("\n" + key + ": ");
    EXPECT_NE(at, std::string::npos) << key;
    text.replace(at + 1, text.find('\n', at + 1) - at - 1, line);
    return text;
  };
  int right1 = 0, right2 = 0, right3 = 0, written3 = 0, runs = 0;
  for (const auto& [file, counts, truth] :
       {std::tuple{"torus-multiaxial.yaml", std::vector<int>{6, 9}, json::array({1, 1, 0})},
        std::tuple{"genus2-random.yaml", std::vector<int>{30, 40}, json::array({1, 2, 0})}}) {
    const std::string base = test::slurp(fs::path(XSECT_SOURCE_DIR) / "configs/phantoms" / file);
    for (const int count : counts)
      for (int seed = 1; seed <= 8; ++seed) {
        const std::string tag = std::string("m3-sparse-") + file + "-" + std::to_string(count) + "-" + std::to_string(seed);
        SCOPED_TRACE(tag);
        const std::string spec =
            withLine(withLine(base, "seed", "seed: " + std::to_string(seed)), "pattern",
                     "pattern: {kind: random, count: " + std::to_string(count) + "}");
        const fs::path dir = test::phantom(tag, spec);
        const json m1 = test::run(dir, "m1", "--set reconstruction.method=nearest_plane");
        const json m2 = test::run(dir, "m2", "--set reconstruction.method=section_voronoi");
        right1 += m1["betti"] == truth;
        right2 += m2["betti"] == truth;
        ++runs;
        // Method 3 joins sections of different planes: with one plane holding sections (the
        // torus, 6 planes, seed 6) it refuses the setting, and counts as wrong.
        const auto r3 = test::runXsect("run " + (dir / "ph/config.yaml").string() + " --out " + (dir / "m3").string() +
                                       " --quiet --set reconstruction.method=delaunay");
        if (r3.code != 0) {
          EXPECT_EQ(r3.code, 2) << r3.err;
          EXPECT_NE(r3.err.find("only one plane holds sections"), std::string::npos) << r3.err;
          std::cout << tag << ": method 1 " << m1["betti"] << ", method 2 " << m2["betti"] << ", method 3 refused\n";
          continue;
        }
        const json m3 = test::readJson(dir / "m3/report.json");
        const json& d = m3["reconstruction"]["delaunay"];
        // R'' itself (its glued boundary), and what the run wrote: the same solid unless no voxel
        // set on the grid has the boundary's Betti numbers (issue 49: then the voxels' solid).
        const json boundary = d["boundary_betti"].is_null() ? m3["betti"] : d["boundary_betti"];
        std::cout << tag << ": method 1 " << m1["betti"] << ", method 2 " << m2["betti"] << ", method 3 " << m3["betti"]
                  << " (R'' " << boundary << ", mesh from " << d["mesh_source"] << ", tunnels cut "
                  << d["cell_tunnels_cut"] << ")\n";
        EXPECT_EQ(m3["voxel_betti"], m3["betti"]);
        right3 += boundary == truth;
        written3 += m3["betti"] == truth;
      }
  }
  std::cout << "truth's topology: method 3 on " << right3 << " of " << runs << " (as written: " << written3
            << "), method 1 on " << right1 << ", method 2 on " << right2 << "\n";
  EXPECT_GT(right3, right1);
  EXPECT_GT(right3, right2);
  // What is written: no worse than method 1, better than method 2 (measured 13, 13, 11).
  EXPECT_GE(written3, right1);
  EXPECT_GT(written3, right2);
}

// A fan of planes (a rotating probe: every plane through one axis) crossing the object: each
// contour crosses the axis on all the other planes at once, outside the general position method 3
// assumes (ch. 3 §2.4), and the run once ended with an open mesh and "a defect of xsect" (exit 1).
// Now it is refused as a setting: exit 2 naming reconstruction.method, nothing written; the same
// slices reconstruct with methods 1 and 2, with the truth's Betti numbers.
TEST(AcceptanceMethod3, AFanOfPlanesThroughTheSectionsIsRefused) {
  const fs::path dir = test::phantom(
      "m3-fan", "seed: 8\nshape: {kind: ellipsoid, params: {a: 10, b: 7, c: 5}, rotation_deg: [0, 25, 0]}\n"
                "pattern: {kind: fan, count: 12, axis: [0, 0, 1], span_deg: 180}\nimage: {pixel_mm: 0.25}\n"
                "config: {reconstruction: {voxel_size_mm: 0.4}}\n");
  test::expectRefused(dir, "reconstruction.method=delaunay");
  const auto r = test::runXsect("run " + (dir / "ph/config.yaml").string() + " --out " + (dir / "out").string() +
                                " --set reconstruction.method=delaunay");
  EXPECT_NE(r.err.find("general position"), std::string::npos) << r.err;
  for (const char* method : {"nearest_plane", "section_voronoi"}) {
    test::run(dir, method, std::string("--set reconstruction.method=") + method);
    const json e = test::eval(dir, method);
    EXPECT_EQ(e["betti"], e["truth_betti"]) << method;
  }
}

// 400 random planes through the genus-2 solid (configs/phantoms/genus2-random-400.yaml, the bench
// scenario random-400 with method 3): the glued boundary is closed. Before, two crossings of a
// plane's constraints within a hundredth of a sample spacing of trace points left 11 open edges
// (the points they made were never welded, and one flat triangle was lost to its slivers), and
// `xsect run` refused the mesh as a defect.
TEST(AcceptanceMethod3, FourHundredRandomPlanesGiveAClosedMesh) {
  const json r = closedRandomPlanesRun(
      "m3-random-400", test::slurp(fs::path(XSECT_SOURCE_DIR) / "configs/phantoms/genus2-random-400.yaml"));
  const json& d = r["reconstruction"]["delaunay"];
  std::cerr << "random-400, method 3: betti " << r["betti"] << ", holes closed " << d["holes_closed"] << ", welded "
            << d["welded_vertices"] << "\n";
}

// Random plane sets through the genus-2 solid (configs/phantoms/genus2-random-200.yaml with other
// seeds and counts). 300 planes, seed 1: two holes of four edges on one plane each, next to three
// planes' corners where a trace point lies 0.005 mm from the corner, were left open (exit 1); now
// closed as flat faces. 200 planes, seed 2: a sliver tetrahedron (four points on different planes
// but nearly coplanar, 3e-8 mm thick) that the pinch handling parted from the solid made a second
// surface of no volume; now dropped. Both: one closed surface, no cavity. (Their b1 is 3, not the
// truth's 2: the sampling verdict is "violated" on both; see docs/methods.md on method 3.)
TEST(AcceptanceMethod3, RandomPlaneSetsGiveOneClosedSurface) {
  const std::string spec = test::slurp(fs::path(XSECT_SOURCE_DIR) / "configs/phantoms/genus2-random-200.yaml");
  for (const auto& [count, seed] : {std::pair{300, 1}, std::pair{200, 2}}) {
    const std::string tag = "m3-random-" + std::to_string(count) + "-" + std::to_string(seed);
    SCOPED_TRACE(tag);
    std::string s = spec;
    s.replace(s.find("seed: 5"), 7, "seed: " + std::to_string(seed));
    s.replace(s.find("count: 200"), 10, "count: " + std::to_string(count));
    const json r = closedRandomPlanesRun(tag, s);
    const json& d = r["reconstruction"]["delaunay"];
    EXPECT_EQ(r["betti"][2], 0);
    EXPECT_GE((count == 300 ? d["holes_closed"] : d["flat_shells_dropped"]).get<int>(), 1);  // the repair ran
    std::cerr << tag << ": betti " << r["betti"] << ", holes closed " << d["holes_closed"] << ", flat shells dropped "
              << d["flat_shells_dropped"] << "\n";
  }
}
