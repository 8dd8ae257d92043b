// Issue 15 (first part): degenerate slice geometry through `xsect run`. Frames listed twice (the
// same image at the same pose) crashed the arrange stage with SIGFPE: the exact sign said an
// edge crossed the repeated plane while the rounded distances were both about 0, and 0/0 reached
// CGAL's exact predicate. Repeats are now merged with a warning, and a crossing the rounding
// cannot place is taken at the edge's midpoint.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>

#include <functional>

#include <nlohmann/json.hpp>

#include "io/slices_file.h"
#include "phantom_runs.h"

namespace fs = std::filesystem;
using json = nlohmann::json;
using namespace xsect;

namespace {

/// An ellipsoid cut by 16 planes through one axis (oblique to each other, as where it crashed).
fs::path fanPhantom(const std::string& tag) {
  return test::phantom(tag, "seed: 2\nshape: {kind: ellipsoid, params: {a: 8, b: 6, c: 5}, rotation_deg: [10, 20, 0]}\n"
                            "pattern: {kind: fan, count: 16, axis: [0.2, 0.1, 1]}\nimage: {pixel_mm: 0.2}\n");
}

/// Writes dir/ph/<name>.yaml holding exactly `slices`, and a configuration reading it.
fs::path withSliceList(const fs::path& dir, const std::string& name, const std::vector<SliceRecord>& slices) {
  writeSlicesFile((dir / "ph" / (name + ".yaml")).string(), slices);
  std::string config = test::slurp(dir / "ph/config.yaml");
  const auto at = config.find("slices.yaml");
  config.replace(at, std::string("slices.yaml").size(), name + ".yaml");
  test::writeFile(dir / "ph" / (name + "_config.yaml"), config);
  return dir / "ph" / (name + "_config.yaml");
}

/// Writes dir/ph/<name>.yaml: the phantom's slices plus `extra`, and a configuration reading it.
fs::path withSlices(const fs::path& dir, const std::string& name, const std::vector<SliceRecord>& extra) {
  std::vector<SliceRecord> slices = readSlicesFile((dir / "ph/slices.yaml").string());
  slices.insert(slices.end(), extra.begin(), extra.end());
  return withSliceList(dir, name, slices);
}

/// The slice moved by `shift` (mm, world) and turned by `angle_deg` about its image centre's u axis.
SliceRecord moved(SliceRecord s, const Vec3& shift, double angle_deg = 0.0) {
  Mat4& m = s.image_to_world;
  const Vec3 u = m.block<3, 1>(0, 0).normalized();
  const Vec3 centre = m.block<3, 1>(0, 3);  // pixel (0, 0): any point of the plane will do
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle_deg * std::acos(-1.0) / 180.0, u).toRotationMatrix();
  m.block<3, 3>(0, 0) = R * m.block<3, 3>(0, 0);
  m.block<3, 1>(0, 3) = R * (m.block<3, 1>(0, 3) - centre) + centre + shift;
  return s;
}

Vec3 normalOf(const SliceRecord& s) {
  return s.image_to_world.block<3, 1>(0, 0).cross(s.image_to_world.block<3, 1>(0, 1)).normalized();
}

json runConfig(const fs::path& config, const fs::path& out) {
  const auto r = test::runXsect("run " + config.string() + " --out " + out.string() + " --quiet");
  EXPECT_EQ(r.code, 0) << r.err;
  return test::readJson(out / "report.json");
}

}  // namespace

TEST(DegenerateSlices, FramesListedTwiceAreMergedWithAWarning) {
  const fs::path dir = fanPhantom("repeated");
  const std::vector<SliceRecord> slices = readSlicesFile((dir / "ph/slices.yaml").string());
  const json base = runConfig(dir / "ph/config.yaml", dir / "base");
  // The whole list twice, as when two lists are concatenated.
  const json rep = runConfig(withSlices(dir, "twice", slices), dir / "twice");
  EXPECT_EQ(rep["betti"], json::array({1, 0, 0}));
  EXPECT_EQ(rep["counts"]["slices"], slices.size());
  int merged = 0;
  for (const json& w : rep["warnings"])
    merged += w.get<std::string>().find("the same image at the same pose): merged") != std::string::npos;
  EXPECT_EQ(merged, int(slices.size()));
  EXPECT_NE(rep["warnings"].dump().find("slices[" + std::to_string(slices.size()) + "] (" + slices[0].image +
                                        ") repeats slices[0]"),
            std::string::npos);
  // The same solid as without the repeats.
  EXPECT_EQ(test::slurp(dir / "twice/mesh.ply"), test::slurp(dir / "base/mesh.ply"));
  fs::remove_all(dir);
}

TEST(DegenerateSlices, CoincidentPlanesWithDifferentSectionsRun) {
  // Frame k's pose with frame k+1's image: two observations of one plane that disagree. Stage 3
  // reports each pair and replaces it by one plane with their consensus; the run completes with a
  // closed solid of the object's topology.
  const fs::path dir = fanPhantom("coincident");
  const std::vector<SliceRecord> slices = readSlicesFile((dir / "ph/slices.yaml").string());
  std::vector<SliceRecord> extra;
  for (std::size_t k = 2; k + 1 < slices.size(); k += 3) {
    SliceRecord s = slices[k];
    s.image = slices[k + 1].image;
    s.image_resolved = slices[k + 1].image_resolved;
    extra.push_back(s);
  }
  const json rep = runConfig(withSlices(dir, "coincident", extra), dir / "out");
  EXPECT_EQ(rep["betti"][0], 1);
  EXPECT_TRUE(rep["watertight"].get<bool>());
  EXPECT_EQ(rep["counts"]["slices"], slices.size() + extra.size());
  const json& groups = rep["conformity"]["coincident_planes"];
  ASSERT_EQ(groups.size(), extra.size()) << groups;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const int k = int(2 + 3 * g);
    EXPECT_EQ(groups[g]["slices"], json::array({k, int(slices.size() + g)}));
    EXPECT_GT(groups[g]["disagreement_area_mm2"].get<double>(), 0.5);
    EXPECT_GT(groups[g]["max_correction_mm"].get<double>(), 0.01);
    EXPECT_LT(groups[g]["max_offset_mm"].get<double>(), 1e-6);
  }
  EXPECT_NE(rep["warnings"].dump().find("observe one plane"), std::string::npos) << rep["warnings"];
  EXPECT_EQ(rep["betti"], json::array({1, 0, 0}));
  fs::remove_all(dir);
}

TEST(DegenerateSlices, CslCountsAreCheckedBeforeAllocation) {
  // Counts a corrupt file claims are checked against what it holds (issue 15, item 3): exit 2
  // naming the field, not an allocation failure.
  const fs::path dir = test::freshDir("csl-counts");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"CSLC\n1000000000000 1\n1 0 0 0 0 1 0\n", "plane count"},
      {"CSLC\n1 1\n1 999999999999 1 0 0 1 0\n0 0 0\n", "plane 1 vertex count"},
      {"CSLC\n1 1\n1 3 88888888888 0 0 1 0\n0 0 0\n1 0 0\n0 1 0\n3 1 0 1 2\n", "plane 1 component count"},
      {"CSLC\n1 1\n1 3 1 0 0 1 0\n0 0 0\n1 0 0\n0 1 0\n77777777777 1 0 1 2\n", "plane 1 component 0"},
  };
  for (const auto& [text, field] : cases) {
    SCOPED_TRACE(field);
    test::writeFile(dir / "bad.csl", text);
    test::writeFile(dir / "config.yaml", "input:\n  csl: bad.csl\n");
    const auto r = test::runXsect("run " + (dir / "config.yaml").string() + " --out " + (dir / "out").string() +
                                  " --quiet");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("bad.csl"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(field), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
  }
  fs::remove_all(dir);
}

TEST(DegenerateSlices, CslRingsWithoutAreaAreDroppedAndSelfIntersectingOnesRefused) {
  const fs::path dir = test::freshDir("csl-rings");
  // Plane 1: a segment (collinear ring, the section of a tangent plane) beside a square; plane 2:
  // a square with a repeated vertex. Runs, the segment dropped with a warning naming it.
  const std::string good =
      "CSLC\n2 1\n"
      "1 7 2 0 0 1 0\n0 0 0\n1 1 0\n2 2 0\n3 0 0\n5 0 0\n5 2 0\n3 2 0\n3 1 0 1 2\n4 1 3 4 5 6\n"
      "2 5 1 0 0 1 -1\n3 0 1\n5 0 1\n5 0 1\n5 2 1\n3 2 1\n5 1 0 1 2 3 4\n";
  test::writeFile(dir / "good.csl", good);
  test::writeFile(dir / "good.yaml", "input:\n  csl: good.csl\n");
  auto r = test::runXsect("run " + (dir / "good.yaml").string() + " --out " + (dir / "out").string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const json rep = test::readJson(dir / "out/report.json");
  EXPECT_NE(rep["warnings"].dump().find("plane 1 component 0 has no area (a point or a segment): dropped"),
            std::string::npos)
      << rep["warnings"];
  EXPECT_EQ(rep["counts"]["sections"], 2);
  EXPECT_EQ(rep["betti"], json::array({1, 0, 0}));
  // A bow tie with unequal lobes: made simple by default (issue 49, tests/test_ring_repair.cpp);
  // with input.repair_contours: false refused, naming plane and component.
  test::writeFile(dir / "bad.csl", "CSLC\n1 1\n1 4 1 0 0 1 0\n0 0 0\n3 2 0\n3 0 0\n0 1 0\n4 1 0 1 2 3\n");
  test::writeFile(dir / "bad.yaml", "input:\n  csl: bad.csl\n  repair_contours: false\n");
  r = test::runXsect("run " + (dir / "bad.yaml").string() + " --out " + (dir / "bad").string() + " --quiet");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("bad.csl:3: plane 1 component 0: the contour crosses itself"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "bad"));
  fs::remove_all(dir);
}

TEST(DegenerateSlices, NearlyCoincidentAndNearlyParallelPlanes) {
  // Beside frames 3 and 9: their own image 3 pixels (0.6 mm) along the normal (nearly coincident,
  // distinct planes) and the next frame turned by 0.5 degree about its image's u axis (nearly
  // parallel: its far edge 0.26 mm off the frame's plane). Turned by 1e-5 degree instead (5e-6 mm,
  // within a thousandth of a pixel), it observes the frame's plane: merged.
  const fs::path dir = fanPhantom("nearly");
  const std::vector<SliceRecord> slices = readSlicesFile((dir / "ph/slices.yaml").string());
  std::vector<SliceRecord> extra;
  for (const std::size_t k : {3u, 9u}) {
    extra.push_back(moved(slices[k], 0.6 * normalOf(slices[k])));
    extra.push_back(moved(slices[k + 1], Vec3::Zero(), 0.5));
  }
  json rep = runConfig(withSlices(dir, "nearly", extra), dir / "out");
  EXPECT_TRUE(rep["watertight"].get<bool>());
  EXPECT_EQ(rep["betti"], json::array({1, 0, 0}));
  EXPECT_TRUE(rep["conformity"]["coincident_planes"].empty()) << rep["conformity"]["coincident_planes"];
  extra = {moved(slices[4], Vec3::Zero(), 1e-5)};
  rep = runConfig(withSlices(dir, "turned", extra), dir / "turned");
  EXPECT_TRUE(rep["watertight"].get<bool>());
  EXPECT_EQ(rep["betti"], json::array({1, 0, 0}));
  ASSERT_EQ(rep["conformity"]["coincident_planes"].size(), 1u);
  EXPECT_EQ(rep["conformity"]["coincident_planes"][0]["slices"], json::array({4, int(slices.size())}));
  fs::remove_all(dir);
}

TEST(DegenerateSlices, PlanesThroughContourVerticesAndCommonLines) {
  // The octahedron |x| + |y| + |z| <= 2 cut by z = 0, x = 0, y = 0, x = y and x = -y: three planes
  // meet at the origin, four share the z axis, and every common line passes through vertices of
  // the other planes' contours (the diamonds' corners) or the midpoints of their edges.
  const fs::path dir = test::freshDir("through_vertices");
  test::writeFile(dir / "octahedron.csl",
                  "CSLC\n5 1\n"
                  "1 4 1 0 0 1 0\n2 0 0\n0 2 0\n-2 0 0\n0 -2 0\n4 1 0 1 2 3\n"
                  "2 4 1 1 0 0 0\n0 2 0\n0 0 2\n0 -2 0\n0 0 -2\n4 1 0 1 2 3\n"
                  "3 4 1 0 1 0 0\n2 0 0\n0 0 2\n-2 0 0\n0 0 -2\n4 1 0 1 2 3\n"
                  "4 4 1 1 -1 0 0\n1 1 0\n0 0 2\n-1 -1 0\n0 0 -2\n4 1 0 1 2 3\n"
                  "5 4 1 1 1 0 0\n1 -1 0\n0 0 2\n-1 1 0\n0 0 -2\n4 1 0 1 2 3\n");
  test::writeFile(dir / "config.yaml", "input:\n  csl: octahedron.csl\n");
  const json rep = runConfig(dir / "config.yaml", dir / "out");
  EXPECT_TRUE(rep["watertight"].get<bool>());
  EXPECT_EQ(rep["betti"], json::array({1, 0, 0}));
  EXPECT_EQ(rep["counts"]["sections"], 5);
  fs::remove_all(dir);
}

TEST(DegenerateSlices, ASingleSliceAndEverySliceAtOnePose) {
  // One slice: its section extended to the end planes, with a warning that the shape across the
  // plane is unknown. Every slice at frame 5's pose with its own image: stage 3 merges the sixteen
  // observations of one plane into one consensus, and the same warning follows.
  const fs::path dir = fanPhantom("one_plane");
  const std::vector<SliceRecord> slices = readSlicesFile((dir / "ph/slices.yaml").string());
  json rep = runConfig(withSliceList(dir, "single", {slices[5]}), dir / "single");
  EXPECT_TRUE(rep["watertight"].get<bool>());
  EXPECT_EQ(rep["betti"], json::array({1, 0, 0}));
  EXPECT_NE(rep["warnings"].dump().find("only one plane holds sections (slice 0)"), std::string::npos)
      << rep["warnings"];
  std::vector<SliceRecord> onePose = slices;
  for (SliceRecord& s : onePose) s.image_to_world = slices[5].image_to_world;
  rep = runConfig(withSliceList(dir, "one_pose", onePose), dir / "one_pose");
  EXPECT_TRUE(rep["watertight"].get<bool>());
  EXPECT_EQ(rep["betti"], json::array({1, 0, 0}));
  ASSERT_EQ(rep["conformity"]["coincident_planes"].size(), 1u);
  EXPECT_EQ(rep["conformity"]["coincident_planes"][0]["slices"].size(), slices.size());
  EXPECT_NE(rep["warnings"].dump().find("only one plane holds sections"), std::string::npos) << rep["warnings"];
  fs::remove_all(dir);
}

TEST(DegenerateSlices, SectionsOnePixelWide) {
  // A dot, a one-pixel line, a 3 x 3 block on parallel frames and a one-pixel line across them. At
  // the automatic voxel (half a pixel) the images hardly resolve them: exit 2 naming the voxel size
  // to use. With it, a closed solid.
  const fs::path dir = test::freshDir("one_pixel");
  const auto image = [&](const std::string& name, const std::function<bool(int, int)>& on) {
    cv::Mat m(40, 40, CV_8U, cv::Scalar(0));
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i) m.at<unsigned char>(j, i) = on(i, j) ? 255 : 0;
    cv::imwrite((dir / name).string(), m);
  };
  image("dot.png", [](int i, int j) { return i == 20 && j == 20; });
  image("line.png", [](int i, int j) { return j == 20 && i >= 12 && i < 28; });
  image("block.png", [](int i, int j) { return i >= 19 && i < 22 && j >= 19 && j < 22; });
  image("across.png", [](int i, int j) { return i == 20 && j >= 14 && j < 26; });
  test::writeFile(dir / "slices.yaml",
                  "slices:\n"
                  "  - {image: dot.png, image_to_world: [[0.25, 0, 0, -5], [0, 0.25, 0, -5], [0, 0, 1, 0], [0, 0, 0, 1]]}\n"
                  "  - {image: line.png, image_to_world: [[0.25, 0, 0, -5], [0, 0.25, 0, -5], [0, 0, 1, 0.5], [0, 0, 0, 1]]}\n"
                  "  - {image: block.png, image_to_world: [[0.25, 0, 0, -5], [0, 0.25, 0, -5], [0, 0, 1, 1], [0, 0, 0, 1]]}\n"
                  "  - {image: across.png, image_to_world: [[0, 0, 1, 0], [0.25, 0, 0, -5], [0, 0.25, 0, -4], [0, 0, 0, 1]]}\n");
  test::writeFile(dir / "config.yaml", "input: {slices: slices.yaml}\nsegmentation: {method: threshold, threshold: 128}\n");
  auto r = test::runXsect("run " + (dir / "config.yaml").string() + " --out " + (dir / "auto").string() + " --quiet");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("reconstruction.voxel_size_mm"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("narrower than two voxels"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("set reconstruction.voxel_size_mm: 0.063"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "auto"));
  r = test::runXsect("run " + (dir / "config.yaml").string() + " --out " + (dir / "fine").string() +
                     " --quiet --set reconstruction.voxel_size_mm=0.063");
  ASSERT_EQ(r.code, 0) << r.err;
  const json rep = test::readJson(dir / "fine/report.json");
  EXPECT_TRUE(rep["watertight"].get<bool>());
  EXPECT_EQ(rep["counts"]["sections"], 4);
  EXPECT_EQ(rep["betti"], json::array({1, 0, 0}));
  fs::remove_all(dir);
}

TEST(DegenerateSlices, CoordinatesFarFromTheOriginAndInTinyUnits) {
  // The fan phantom in micrometres' worth of millimetres (every length times 1e-3) and 10 m from the
  // origin: the same solid. 10 km from the origin, single-precision meshes cannot hold a 0.2 mm
  // voxel: exit 2 saying so, nothing written.
  const fs::path dir = fanPhantom("far_tiny");
  const std::vector<SliceRecord> slices = readSlicesFile((dir / "ph/slices.yaml").string());
  const auto transformed = [&](double scale, double shift) {
    std::vector<SliceRecord> out = slices;
    for (SliceRecord& s : out) {
      s.image_to_world.block<3, 4>(0, 0) *= scale;
      s.image_to_world.block<3, 1>(0, 3) += Vec3::Constant(shift);
    }
    return out;
  };
  json rep = runConfig(withSliceList(dir, "tiny", transformed(1e-3, 0.0)), dir / "tiny");
  EXPECT_TRUE(rep["watertight"].get<bool>());
  EXPECT_EQ(rep["betti"], json::array({1, 0, 0}));
  EXPECT_LT(rep["reconstruction"]["voxel_size"]["voxel_size_mm"].get<double>(), 1e-3);
  rep = runConfig(withSliceList(dir, "far", transformed(1.0, 1e4)), dir / "far");
  EXPECT_TRUE(rep["watertight"].get<bool>());
  EXPECT_EQ(rep["betti"], json::array({1, 0, 0}));
  const auto r = test::runXsect("run " + withSliceList(dir, "farther", transformed(1.0, 1e7)).string() + " --out " +
                                (dir / "farther").string() + " --quiet");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("translate the data nearer the origin"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "farther"));
  fs::remove_all(dir);
}
