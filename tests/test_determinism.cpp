// Output is deterministic: the same inputs and configuration give byte-identical meshes, graphs
// label volumes, conformity reports and (smoothing) level sets whatever the thread count, with
// each of the three methods, with conformity enforced and with pose correction (report.json differs only in
// timings; manifest.json records threads; report.html only in its block of timings and memory).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "cli.h"

namespace fs = std::filesystem;

using xsect::test::slurp;

TEST(Determinism, SameBytesWhateverTheThreadCount) {
  const fs::path dir = xsect::test::freshDir("determinism");
  xsect::test::writeFile(dir / "spec.yaml",
                         "seed: 11\nshape: {kind: torus, params: {major_radius: 9, minor_radius: 3.5},"
                         " rotation_deg: [30, 20, 0]}\npattern: {kind: random, count: 60}\n"
                         "image: {pixel_mm: 0.25}\nconfig: {reconstruction: {voxel_size_mm: 0.35},"
                         " output: {mesh: [ply, stl, obj]}}\n");
  auto r = xsect::test::runXsect("phantom " + (dir / "spec.yaml").string() + " --out " + (dir / "ph").string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const std::string method :
       {"nearest_plane", "section_voronoi", "delaunay", "shepard", "level_set", "conform", "pose"}) {
    SCOPED_TRACE(method);
    // level_set: with adaptive meshing and the automatic voxel size.
    const std::string set = method == "shepard"     ? " --set smoothing.method=shepard"
                            : method == "level_set" ? " --set smoothing.method=level_set --set smoothing.adaptivity=0.5"
                                                      " --set reconstruction.voxel_size_mm=auto"
                            : method == "conform"   ? " --set conformity.enforce=true --set conformity.mode=average"
                            : method == "pose"      ? " --set conformity.pose_correction=rigid"
                                                    : " --set reconstruction.method=" + method;
    for (const char* t : {"1", "2", "3"}) {
      r = xsect::test::runXsect("run " + (dir / "ph/config.yaml").string() + " --out " +
                                (dir / (method + t)).string() + " --quiet --threads " + t + set);
      ASSERT_EQ(r.code, 0) << r.err;
    }
    std::vector<std::string> files{"mesh.ply", "mesh.stl", "mesh.obj", "graph.json", "graph.dot", "labels.nrrd"};
    if (method == "shepard" || method == "level_set") files.insert(files.end(), {"level_set.vdb", "mesh_unsmoothed.ply"});
    files.insert(files.end(), {"conformity.json", "sampling.json", "sampling.nrrd"});
    if (fs::exists(dir / (method + "1") / "advice.yaml")) files.push_back("advice.yaml");
    if (method == "pose") files.push_back("corrected_slices.yaml");
    for (const std::string& f : files) {
      const std::string a = slurp(dir / (method + "1") / f);
      EXPECT_GT(a.size(), 100u) << f;
      EXPECT_EQ(a, slurp(dir / (method + "2") / f)) << f;
      EXPECT_EQ(a, slurp(dir / (method + "3") / f)) << f;
    }
    // report.html: the same page but for its block of timings and memory.
    const auto repeatable = [](std::string page) {
      const std::size_t a = page.find("<!--xsect-unrepeatable-begin-->"), b = page.find("<!--xsect-unrepeatable-end-->");
      EXPECT_TRUE(a != std::string::npos && b != std::string::npos && a < b);
      return a < b && b != std::string::npos ? page.erase(a, b - a) : page;
    };
    const std::string page = repeatable(slurp(dir / (method + "1") / "report.html"));
    EXPECT_GT(page.size(), 100000u);
    EXPECT_EQ(page, repeatable(slurp(dir / (method + "2") / "report.html")));
    EXPECT_EQ(page, repeatable(slurp(dir / (method + "3") / "report.html")));
  }
  fs::remove_all(dir);
}
