// Issue 14, the mesh written is the solid reported: every phantom spec of configs/phantoms/ that
// is dense enough for its truth, under both methods and every smoothing, gives a mesh whose Betti
// numbers are those report.json states for the solid it was made from, and those of the truth;
// the smoothed surface is no farther from the truth than the method's own.
//
// Dense enough (measured with both methods and the four smoothings): sphere-multiaxial,
// torus-multiaxial, hollow-sphere-multiaxial, two-spheres-parallel, ellipsoid-fan,
// split-torus-multiaxial. Not: genus2-random (60 random planes: method 2 gives b1 = 3 and
// Shepard with p = 1 b1 = 7, against 2), vessel-tree-sparse (method 1 splits it, by design),
// the thesis Fig. 1.11 pair (reach 0), torus-multiaxial-jitter (tracking error), and the bench
// scenarios, too large for CI (torus-multiaxial-3x40, genus2-random-200/400, vessel-tree-freehand*).
// Cost: 12 tests of 4 runs and 4 evaluations each, about 2 minutes on 2 cores.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cctype>

#include "phantom_runs.h"

namespace fs = std::filesystem;
using json = nlohmann::json;
using namespace xsect;
using test::eval;
using test::readJson;

namespace {

struct MatrixCase {
  const char* spec;    ///< configs/phantoms/<spec>.yaml
  const char* method;  ///< reconstruction.method
};

void PrintTo(const MatrixCase& c, std::ostream* os) { *os << c.spec << " " << c.method; }

std::string caseName(const testing::TestParamInfo<MatrixCase>& info) {
  std::string n = std::string(info.param.spec) + "_" + info.param.method;
  for (char& ch : n)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return n;
}

class TopologyMatrix : public testing::TestWithParam<MatrixCase> {};

TEST_P(TopologyMatrix, MeshHasTheReportedAndTheTrueTopologyWithEverySmoothing) {
  const MatrixCase& mc = GetParam();
  const fs::path dir = test::freshDir(std::string("matrix-") + mc.spec);
  const fs::path spec = fs::path(XSECT_SOURCE_DIR) / "configs/phantoms" / (std::string(mc.spec) + ".yaml");
  const auto ph = test::runXsect("phantom " + spec.string() + " --out " + (dir / "ph").string() + " --quiet");
  ASSERT_EQ(ph.code, 0) << ph.err;

  struct Smoothing {
    const char* name;
    std::string sets;
  };
  const std::vector<Smoothing> smoothings = {
      {"none", ""},
      {"shepard1", "--set smoothing.method=shepard --set smoothing.exponent=1"},
      {"shepard2", "--set smoothing.method=shepard --set smoothing.exponent=2"},
      {"level_set", "--set smoothing.method=level_set"},
  };
  double methodDistance = 0;
  for (const Smoothing& s : smoothings) {
    SCOPED_TRACE(s.name);
    const auto r = test::runXsect("run " + (dir / "ph/config.yaml").string() + " --out " + (dir / s.name).string() +
                                  " --quiet --set reconstruction.method=" + mc.method + " " + s.sets);
    ASSERT_EQ(r.code, 0) << r.err;
    const json rep = readJson(dir / s.name / "report.json");
    const json e = eval(dir, s.name);
    // The mesh read back from the file, the report's statement and the truth agree.
    EXPECT_EQ(e["betti"], rep["betti"]);
    EXPECT_EQ(rep["betti"], e["truth_betti"]);
    EXPECT_TRUE(e["watertight"].get<bool>());
    if (std::string(s.name) == "none") {
      EXPECT_EQ(rep["betti"], rep["voxel_betti"]);
      methodDistance = e["mean_distance_mm"].get<double>();
    } else {
      EXPECT_EQ(rep["betti"], rep["smoothing"]["voxel_betti"]);
      EXPECT_EQ(rep["smoothing"]["unsmoothed"]["betti"], rep["voxel_betti"]);
      EXPECT_LE(e["mean_distance_mm"].get<double>(), methodDistance)
          << s.name << " is farther from the truth than the method's own surface";
    }
    for (const json& m : rep["materials"]) EXPECT_EQ(m["betti"], m["voxel_betti"]) << m;
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(
    DensePhantoms, TopologyMatrix,
    testing::Values(MatrixCase{"sphere-multiaxial", "nearest_plane"}, MatrixCase{"sphere-multiaxial", "section_voronoi"},
                    MatrixCase{"torus-multiaxial", "nearest_plane"}, MatrixCase{"torus-multiaxial", "section_voronoi"},
                    MatrixCase{"hollow-sphere-multiaxial", "nearest_plane"},
                    MatrixCase{"hollow-sphere-multiaxial", "section_voronoi"},
                    MatrixCase{"two-spheres-parallel", "nearest_plane"},
                    MatrixCase{"two-spheres-parallel", "section_voronoi"},
                    MatrixCase{"ellipsoid-fan", "nearest_plane"}, MatrixCase{"ellipsoid-fan", "section_voronoi"},
                    MatrixCase{"split-torus-multiaxial", "nearest_plane"},
                    MatrixCase{"split-torus-multiaxial", "section_voronoi"}),
    caseName);

}  // namespace
