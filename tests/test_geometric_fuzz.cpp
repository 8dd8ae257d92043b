// Issue 15: the geometric fuzzer (geometric_fuzz.h) through `xsect run`, in four shards of 75
// configurations (CI's budget is 25 minutes from a clean build; `scripts/fuzz.sh` runs more;
// XSECT_FUZZ_CONFIGS overrides the count per shard, XSECT_FUZZ_SEED the first seed). Every run
// gives, within two minutes, exit 0 with a watertight mesh (read back from the file written) whose
// Betti numbers are the report's and the solid's, or exit 2 with a message naming the
// configuration or the input file.
#include <gtest/gtest.h>

#include <cstdlib>
#include <nlohmann/json.hpp>

#include "geometric_fuzz.h"
#include "geometry/meshing/mesh_topology.h"
#include "io/mesh_io.h"
#include "phantom_runs.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

std::uint64_t envNumber(const char* name, std::uint64_t fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::strtoull(v, nullptr, 10) : fallback;
}

class GeometricFuzz : public testing::TestWithParam<int> {};

TEST_P(GeometricFuzz, RandomDegenerateConfigurationsExitCleanly) {
  const std::uint64_t count = envNumber("XSECT_FUZZ_CONFIGS", 75);
  const std::uint64_t first = envNumber("XSECT_FUZZ_SEED", 1) + std::uint64_t(GetParam()) * count;
  int ok = 0, refused = 0;
  for (std::uint64_t seed = first; seed < first + count; ++seed) {
    const xsect::test::FuzzCase f = xsect::test::geometricFuzzCase(seed);
    const fs::path dir = xsect::test::freshDir("fuzz");
    xsect::test::writeFile(dir / "input.csl", f.csl);
    xsect::test::writeFile(dir / "config.yaml", f.config);
    const auto r = xsect::test::runXsect("run " + (dir / "config.yaml").string() + " --quiet", 120);
    if (r.code == 0) {
      ++ok;
      const json rep = xsect::test::readJson(dir / "out/report.json");
      const xsect::MeshTopology t = xsect::meshTopology(xsect::readMesh((dir / "out/mesh.ply").string()));
      EXPECT_TRUE(t.watertight) << f.what;
      EXPECT_EQ(json(t.betti), rep["betti"]) << f.what;
      EXPECT_EQ(rep["betti"], rep.contains("smoothing") ? rep["smoothing"]["voxel_betti"] : rep["voxel_betti"])
          << f.what;
    } else if (r.code == 2) {
      ++refused;
      EXPECT_NE(r.err.find("xsect: error: "), std::string::npos) << f.what << "\n" << r.err;
      EXPECT_TRUE(r.err.find("input.csl") != std::string::npos || r.err.find("config.yaml") != std::string::npos)
          << f.what << "\n" << r.err;
    } else {
      ADD_FAILURE() << f.what << ": exit " << r.code << "\n" << r.err << "\n" << f.csl.substr(0, 4000);
    }
    fs::remove_all(dir);
  }
  RecordProperty("exit_0", ok);
  RecordProperty("exit_2", refused);
  std::cerr << "geometric fuzz shard " << GetParam() << ": " << ok << " exit 0, " << refused << " exit 2 of " << count
            << "\n";
}

INSTANTIATE_TEST_SUITE_P(Shards, GeometricFuzz, testing::Values(0, 1, 2, 3));

}  // namespace
