// The phantom families of the acceptance tests of methods 1 and 2 (tests/test_acceptance_method1.cpp,
// tests/test_acceptance_method2.cpp): five shapes, each with plane counts whose spacing is well
// below its reach, and the check of one case through the command line (phantom -> run -> eval):
// the phantom's Betti numbers, a Hausdorff distance below the method's bound (method 1: the
// largest gap between neighbouring parallel planes, or for random planes twice the largest distance
// from a point of the solid to its nearest plane; method 2: the longest lift segment plus a voxel,
// Thm 20, where the Weak Density Condition holds), and conformity IoU >= 0.97 on every plane
// whose section spans at least 10 voxels.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "geometry/core/plane_of_pose.h"
#include "geometry/phantoms/phantom_shape.h"
#include "io/slices_file.h"
#include "io/truth_file.h"

namespace xsect::test::families {

namespace fs = std::filesystem;
using json = nlohmann::json;

struct Case {
  std::string name, shape, pattern;
  double voxel;
  std::string degradations = "{}";
  bool checkConformity = true;
  double extraBound = 0;  // mm added to the Hausdorff bound (recorded-pose error)
  std::string method = "nearest_plane";
};

struct Shape {
  std::string name, yaml;
  int multiaxial, parallel, random;  // plane counts giving a spacing well below the reach
};

/// Largest gap between neighbouring parallel planes of the slices (groups of equal normals).
inline double largestParallelGap(const std::vector<SliceRecord>& slices) {
  std::vector<std::pair<Vec3, std::vector<double>>> groups;
  for (const auto& s : slices) {
    const Plane p = planeOfPose(s.image_to_world);
    bool placed = false;
    for (auto& [n, offsets] : groups)
      if (std::abs(std::abs(n.dot(p.normal)) - 1) < 1e-9) {
        offsets.push_back(n.dot(p.origin));
        placed = true;
        break;
      }
    if (!placed) groups.push_back({p.normal, {p.normal.dot(p.origin)}});
  }
  double gap = 0;
  for (auto& [n, o] : groups) {
    std::sort(o.begin(), o.end());
    for (std::size_t i = 1; i < o.size(); ++i) gap = std::max(gap, o[i] - o[i - 1]);
  }
  return gap;
}

/// Largest distance from a point of the solid to its nearest plane (sampled on a 0.5 mm grid).
inline double largestHeightInSolid(const PhantomShape& shape, const std::vector<SliceRecord>& slices) {
  std::vector<Plane> planes;
  for (const auto& s : slices) planes.push_back(planeOfPose(s.image_to_world));
  Vec3 lo, hi;
  bounds(shape, &lo, &hi);
  double worst = 0;
  for (double z = lo.z(); z <= hi.z(); z += 0.5)
    for (double y = lo.y(); y <= hi.y(); y += 0.5)
      for (double x = lo.x(); x <= hi.x(); x += 0.5) {
        const Vec3 p(x, y, z);
        if (signedDistance(shape, p) > 0) continue;
        double d = 1e300;
        for (const auto& pl : planes) d = std::min(d, std::abs(pl.signedDistance(p)));
        worst = std::max(worst, d);
      }
  return worst;
}

/// `xsect phantom` on the spec text, then `xsect run` on its config: DIR/ph and DIR/res.
inline void phantomAndRun(const fs::path& dir, const std::string& spec) {
  test::writeFile(dir / "spec.yaml", spec);
  auto r = test::runXsect("phantom " + (dir / "spec.yaml").string() + " --out " + (dir / "ph").string() +
                          " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  r = test::runXsect("run " + (dir / "ph/config.yaml").string() + " --out " + (dir / "res").string() +
                     " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
}

inline void runCase(const Case& c) {
  SCOPED_TRACE(c.name);
  const fs::path dir = test::freshDir("accept");
  phantomAndRun(dir, "seed: 3\nshape: " + c.shape + "\npattern: " + c.pattern +
                         "\nimage: {pixel_mm: 0.2}\ndegradations: " + c.degradations +
                         "\nconfig: {reconstruction: {voxel_size_mm: " + std::to_string(c.voxel) +
                         ", method: " + c.method + "}}\n");
  if (::testing::Test::HasFatalFailure()) return;
  const auto r = test::runXsect("eval --mesh " + (dir / "res/mesh.ply").string() + " --truth " +
                     (dir / "ph/truth.yaml").string() + " --slices " + (dir / "ph/slices.yaml").string() +
                     " --json " + (dir / "eval.json").string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const json report = json::parse(std::ifstream(dir / "res/report.json"));
  const json ev = json::parse(std::ifstream(dir / "eval.json"));
  const PhantomShape truth = readTruthFile((dir / "ph/truth.yaml").string());
  const auto slices = readSlicesFile((dir / "ph/slices.yaml").string());

  const Betti want = bettiNumbers(truth);
  EXPECT_EQ(report["betti"], json(want)) << "report betti";
  EXPECT_EQ(ev["betti"], json(want)) << "eval betti";
  EXPECT_TRUE(ev["watertight"].get<bool>());

  const bool random = c.pattern.find("random") != std::string::npos;
  // Gaps from the true poses (the recorded ones carry tracking error when jittered).
  const auto truePoses = readSlicesFile((dir / "ph/true_poses.yaml").string());
  // Method 2: Theorem 20, d_H(O, R') <= the longest lift segment [a, lift'(a)] (<= max h'_C),
  // plus a voxel for the sampling, where the Weak Density Condition holds: lifts shorter than the
  // reach (the phantom's reach bounds reach_e from below).
  if (c.method == "section_voronoi")
    EXPECT_LT(report["reconstruction"]["max_lift_mm"].get<double>(), reach(truth)) << "Weak Density";
  const double bound = c.method == "section_voronoi"
                           ? report["reconstruction"]["max_lift_mm"].get<double>() + c.voxel
                           : random ? 2 * largestHeightInSolid(truth, truePoses) : largestParallelGap(truePoses);
  EXPECT_LT(ev["hausdorff_mm"].get<double>(), bound + c.extraBound) << "bound " << bound;
  if (!c.checkConformity) {
    fs::remove_all(dir);
    return;
  }

  // Conformity on planes whose sections span at least 10 voxels across: hydraulic diameter
  // 4 * area / perimeter >= 10 voxels (the diameter, for a disk). IoU's sensitivity to a boundary
  // offset is set by that width, not by the length of a sliver.
  int checked = 0;
  for (const auto& p : ev["conformity"]) {
    if (p["iou"].is_null()) continue;
    const double width = 4 * p["section_area_mm2"].get<double>() / p["section_perimeter_mm"].get<double>();
    if (!(width >= 10 * c.voxel)) continue;  // also skips empty sections (0 / 0)
    ++checked;
    EXPECT_GE(p["iou"].get<double>(), 0.97) << "slice " << p["slice"];
  }
  EXPECT_GT(checked, 3);
  fs::remove_all(dir);
}

inline const std::vector<Shape>& shapes() {
  static const std::vector<Shape> all = {
      {"sphere", "{kind: sphere, params: {radius: 10}, centre: [0.3, -0.2, 0.1]}", 12, 30, 100},
      // reach 4 mm
      {"torus", "{kind: torus, params: {major_radius: 10, minor_radius: 4}, rotation_deg: [20, 10, 0]}",
       16, 36, 140},
      // reach min(offset_radius, hole_radius - offset_radius) = 2.5 mm
      {"genus2",
       "{kind: genus2, params: {disk_radius: 20, hole_radius: 5, hole_offset: 8, offset_radius: 2.5},"
       " rotation_deg: [15, 0, 10]}",
       30, 50, 200},
      // reach min((Ro - Ri) / 2, Ri) = 2.5 mm
      {"hollow", "{kind: hollow_sphere, params: {outer_radius: 11, inner_radius: 6}}", 18, 36, 160},
      // reach min(radius, (separation - 2 radius) / 2) = 4 mm
      {"two", "{kind: two_spheres, params: {radius: 6, separation: 20}}", 16, 36, 140},
  };
  return all;
}


}  // namespace xsect::test::families
