// Issue 15 (first part): degenerate slice geometry through `xsect run`. Frames listed twice (the
// same image at the same pose) crashed the arrange stage with SIGFPE: the exact sign said an
// edge crossed the repeated plane while the rounded distances were both about 0, and 0/0 reached
// CGAL's exact predicate. Repeats are now merged with a warning, and a crossing the rounding
// cannot place is taken at the edge's midpoint.
#include <gtest/gtest.h>

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

/// Writes dir/ph/<name>.yaml: the phantom's slices plus `extra`, and a configuration reading it.
fs::path withSlices(const fs::path& dir, const std::string& name, const std::vector<SliceRecord>& extra) {
  std::vector<SliceRecord> slices = readSlicesFile((dir / "ph/slices.yaml").string());
  slices.insert(slices.end(), extra.begin(), extra.end());
  writeSlicesFile((dir / "ph" / (name + ".yaml")).string(), slices);
  std::string config = test::slurp(dir / "ph/config.yaml");
  const auto at = config.find("slices.yaml");
  config.replace(at, std::string("slices.yaml").size(), name + ".yaml");
  test::writeFile(dir / "ph" / (name + "_config.yaml"), config);
  return dir / "ph" / (name + "_config.yaml");
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
  // Frame k's pose with frame k+1's image: two observations of one plane that disagree. The run
  // completes with a closed solid. (Stage 3 does not yet compare coincident planes' sections: the
  // rest of issue 15.)
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
  // A bow tie with unequal lobes (the symmetric one has no area): refused, naming plane and component.
  test::writeFile(dir / "bad.csl", "CSLC\n1 1\n1 4 1 0 0 1 0\n0 0 0\n3 2 0\n3 0 0\n0 1 0\n4 1 0 1 2 3\n");
  test::writeFile(dir / "bad.yaml", "input:\n  csl: bad.csl\n");
  r = test::runXsect("run " + (dir / "bad.yaml").string() + " --out " + (dir / "bad").string() + " --quiet");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("bad.csl:3: plane 1 component 0: the contour crosses itself"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "bad"));
  fs::remove_all(dir);
}
