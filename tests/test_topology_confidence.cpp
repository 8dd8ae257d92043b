// topology.confidence (geometry/reconstruction/topology_confidence.h): a solid whose features are
// larger than the data's scale is high; a spurious tunnel a voxel thin makes it low; two parts
// facing each other across less than the scale make it medium.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <regex>

#include "geometry/reconstruction/topology_confidence.h"
#include "phantom_runs.h"

namespace xsect {
namespace {

GridSpec cube(int n) {
  GridSpec g;
  g.voxel = 0.5;
  g.dims = {n, n, n};
  return g;
}

/// The voxels of a torus (major radius R, tube r, in voxels) about the axis `axis`, centred.
std::vector<std::uint8_t> torus(const GridSpec& g, double R, double r, const Vec3& axis) {
  const Vec3 c = 0.5 * Vec3(g.dims[0] - 1, g.dims[1] - 1, g.dims[2] - 1);
  const Vec3 n = axis.normalized();
  std::vector<std::uint8_t> in(std::size_t(g.count()), 0);
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const Vec3 p = Vec3(i, j, k) - c;
        const double h = p.dot(n), q = (p - h * n).norm() - R;
        in[std::size_t(g.index(i, j, k))] = std::hypot(q, h) <= r;
      }
  return in;
}

/// A rod one voxel thick along x through the grid's centre row (j, k) from i0 to i1.
void addRod(std::vector<std::uint8_t>& in, const GridSpec& g, int i0, int i1, int j, int k) {
  for (int i = i0; i <= i1; ++i) in[std::size_t(g.index(i, j, k))] = 1;
}

TEST(TopologyConfidence, AThickTorusIsHighAndAVoxelThinRodAcrossItsHoleMakesItLow) {
  std::mt19937_64 rng(52);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 12; ++trial) {
    const GridSpec g = cube(48);
    const double R = 13 + 3 * u(rng), r = 5 + u(rng);  // the hole's radius R - r is at least 4 voxels
    const Vec3 axis(0.15 * u(rng), 0.15 * u(rng), 1.0);
    std::vector<std::uint8_t> in = torus(g, R, r, axis);
    const Betti truth{1, 1, 0};
    ASSERT_EQ(voxelBetti(in, g), truth) << trial;
    // The data's scale: 2 voxels (dense planes): the hole (radius R - r > 5 voxels) and the tube
    // (radius r) are larger.
    const TopologyConfidence high = topologyConfidence(in, g, truth, 1.0);
    EXPECT_EQ(high.level, ConfidenceLevel::high) << trial << " " << confidenceText(high);
    EXPECT_EQ(high.kinds[1].count, 1);
    // Sparse planes: half the cell height (8 voxels) exceeds the tube: the opening cuts it.
    const TopologyConfidence sparse = topologyConfidence(in, g, truth, 4.0);
    EXPECT_EQ(sparse.level, ConfidenceLevel::medium) << trial << " " << confidenceText(sparse);
    EXPECT_GT(sparse.kinds[1].in_doubt_2, 0);
    // A rod a voxel thick across the hole: a second tunnel that an opening by one voxel removes.
    addRod(in, g, int(24 - R), int(24 + R), 24, 24);  // from tube to tube through the centre
    const Betti withRod = voxelBetti(in, g);
    ASSERT_EQ(withRod[1], 2) << trial;
    const TopologyConfidence low = topologyConfidence(in, g, withRod, 1.0);
    EXPECT_EQ(low.level, ConfidenceLevel::low) << trial << " " << confidenceText(low);
    EXPECT_GE(low.kinds[1].in_doubt_1, 1);
    EXPECT_EQ(low.kinds[1].level, ConfidenceLevel::low);
    EXPECT_EQ(low.kinds[2].level, ConfidenceLevel::high);  // no cavity in doubt
  }
}

TEST(TopologyConfidence, TwoSlabsAreMediumWhenNearerThanTheScaleAndLowWhenAVoxelApart) {
  const GridSpec g = cube(48);
  for (const int gap : {1, 5, 12}) {  // voxels of empty space between two facing slabs
    std::vector<std::uint8_t> in(std::size_t(g.count()), 0);
    const int x0 = 4, x1 = x0 + 12 + gap;  // slabs 12 voxels thick (more than the opening's ball), 24 x 24 across
    for (int k = 12; k < 36; ++k)
      for (int j = 12; j < 36; ++j)
        for (int i = 0; i < 48; ++i)
          in[std::size_t(g.index(i, j, k))] = (i >= x0 && i < x0 + 12) || (i >= x1 && i < x1 + 12);
    const Betti b = voxelBetti(in, g);
    ASSERT_EQ(b[0], 2) << gap;
    // Scale 2 mm = 4 voxels: the closing joins slabs facing each other across less than 8 voxels.
    const TopologyConfidence c = topologyConfidence(in, g, b, 2.0);
    const ConfidenceLevel expected = gap <= 1 ? ConfidenceLevel::low : gap < 8 ? ConfidenceLevel::medium : ConfidenceLevel::high;
    EXPECT_EQ(c.level, expected) << "gap " << gap << ": " << confidenceText(c);
    EXPECT_EQ(c.kinds[0].count, 1);  // one component beyond the first
    EXPECT_EQ(c.kinds[0].level, expected);
  }
}

TEST(TopologyConfidence, AnEmptySolidIsHighWithNothingProbed) {
  const GridSpec g = cube(8);
  const TopologyConfidence c = topologyConfidence(std::vector<std::uint8_t>(std::size_t(g.count()), 0), g, {0, 0, 0}, 1.0);
  EXPECT_EQ(c.level, ConfidenceLevel::high);
  EXPECT_EQ(c.voxels, 0);
}

// Pinholes a voxel wide inside a block (cavities a closing by one voxel fills) make it low, and
// the text counts them in words ("2 cavities", "1 cavity").
TEST(TopologyConfidence, VoxelCavitiesAreLowAndCountedInWords) {
  const GridSpec g = cube(20);
  for (const int holes : {1, 2, 3}) {
    std::vector<std::uint8_t> in(std::size_t(g.count()), 0);
    for (int k = 4; k < 16; ++k)
      for (int j = 4; j < 16; ++j)
        for (int i = 4; i < 16; ++i) in[std::size_t(g.index(i, j, k))] = 1;
    for (int h = 0; h < holes; ++h) in[std::size_t(g.index(7 + 3 * h, 10, 10))] = 0;
    const Betti betti = voxelBetti(in, g);
    ASSERT_EQ(betti, (Betti{1, 0, holes}));
    const TopologyConfidence c = topologyConfidence(in, g, betti, 1.0);
    EXPECT_EQ(c.level, ConfidenceLevel::low);
    EXPECT_EQ(c.kinds[2].in_doubt_1, holes);
    const std::string words = std::to_string(holes) + (holes == 1 ? " cavity " : " cavities ");
    EXPECT_NE(confidenceText(c).find(words), std::string::npos) << confidenceText(c);
  }
}

// End to end: the dense torus of configs/phantoms/torus-multiaxial.yaml is rated high (its tube and
// hole are larger than its cells' heights); the same torus cut by 3 planes per axis (cells as high
// as the tube is thick) is not; `xsect check` gives the data's scale before any run.
TEST(TopologyConfidence, ARunRatesADenseTorusHighAndASparseOneLower) {
  const std::string spec =
      "seed: 2\nshape: {kind: torus, params: {major_radius: 12, minor_radius: 4}, rotation_deg: [20, 10, 0]}\n"
      "pattern: {kind: multiaxial, count: COUNT}\nimage: {pixel_mm: 0.25}\n"
      "config: {reconstruction: {voxel_size_mm: 0.4}}\n";
  for (const int count : {10, 3}) {
    std::string s = spec;
    s.replace(s.find("COUNT"), 5, std::to_string(count));
    const std::filesystem::path dir = test::phantom("confidence-torus-" + std::to_string(count), s);
    const nlohmann::json r = test::run(dir, "out", "");
    const nlohmann::json& c = r["topology"]["confidence"];
    ASSERT_TRUE(c.is_object()) << r["topology"].dump();
    EXPECT_EQ(r["topology"]["mode"], "free");
    EXPECT_EQ(c["probes"].size(), 2u);
    EXPECT_DOUBLE_EQ(c["probes"][0]["radius_mm"].get<double>(), 0.4);
    if (count == 10) {
      EXPECT_EQ(r["betti"], nlohmann::json({1, 1, 0}));
      EXPECT_EQ(c["level"], "high") << c.dump();
    } else {
      EXPECT_NE(c["level"], "high") << c.dump();
      EXPECT_GT(c["probes"][1]["radius_mm"].get<double>(), 2.0) << c.dump();  // cells 4+ mm high
    }
    const std::filesystem::path json = dir / "check.json";
    ASSERT_EQ(std::system((std::string(XSECT_BIN) + " check " + (dir / "ph/config.yaml").string() + " --quiet --json > " +
                           json.string()).c_str()),
              0);
    const nlohmann::json k = test::readJson(json);
    EXPECT_TRUE(k["topology"]["confidence"].is_null());
    EXPECT_GE(k["topology"]["data_scale_mm"].get<double>(), c["probes"][1]["radius_mm"].get<double>() - 1e-9)
        << "check bounds the heights from above";
    std::filesystem::remove_all(dir);
  }
}

// The rates docs/topology.md ("Topology confidence") quotes, on a part of the families small enough for CI,
// on seeds 5-8, which the radii were not chosen on (seeds 1-4 chose them): the torus and the sphere
// cut by 6 and 9 random planes, the genus-2 solid by 20, the cup by its 5 mixed planes (tilted as
// bench/topology_family.py tilts it), method 1 (24 configurations). Every high must have the truth's
// topology, high must go to at least half of the right results, and low must be wrong at least 70%
// of the time (measured: high 8 of 8 right, of 13 right results; low 6 of 8 wrong).
TEST(TopologyConfidence, OnSparseFamiliesHighIsRightAndLowIsMostlyWrong) {
  struct Family {
    const char* base;
    std::vector<int> counts;
  };
  int high = 0, highRight = 0, right = 0, low = 0, lowWrong = 0;
  std::string rows;
  // count 0: the phantom's own planes, its rotation drawn from the seed.
  for (const Family& f : {Family{"torus-multiaxial.yaml", {6, 9}}, Family{"sphere-multiaxial.yaml", {6, 9}},
                          Family{"genus2-random.yaml", {20}}, Family{"cup-mixed.yaml", {0}}})
    for (const int count : f.counts)
      for (int seed = 5; seed <= 8; ++seed) {
        std::string spec = test::slurp(std::filesystem::path(XSECT_SOURCE_DIR) / "configs/phantoms" / f.base);
        spec = std::regex_replace(spec, std::regex("(^|\n)seed: [^\n]*"), "$1seed: " + std::to_string(seed));
        if (count > 0)
          spec = std::regex_replace(spec, std::regex("(^|\n)pattern: [^\n]*"),
                                    "$1pattern: {kind: random, count: " + std::to_string(count) + "}");
        else
          spec = std::regex_replace(spec, std::regex("\n  rotation_deg: [^\n]*"),
                                    "\n  rotation_deg: [" + std::to_string((seed * 17) % 31 - 15) + ", " +
                                        std::to_string((seed * 29) % 31 - 15) + ", " + std::to_string((seed * 73) % 360) + "]");
        const std::filesystem::path dir = test::phantom("confidence-family", spec);
        const std::string truthText = test::slurp(dir / "ph/truth.yaml");
        std::smatch m;
        ASSERT_TRUE(std::regex_search(truthText, m, std::regex(R"(\nbetti: \[(\d+), (\d+), (\d+)\])")));
        const nlohmann::json truth = {std::stoi(m[1]), std::stoi(m[2]), std::stoi(m[3])};
        const nlohmann::json r = test::run(dir, "out", "");
        const std::string level = r["topology"]["confidence"]["level"];
        const bool ok = r["betti"] == truth;
        right += ok;
        high += level == "high", highRight += level == "high" && ok;
        low += level == "low", lowWrong += level == "low" && !ok;
        rows += std::string(f.base) + " " + std::to_string(count) + " s" + std::to_string(seed) + ": " + r["betti"].dump() +
                (ok ? " right, " : " wrong, ") + level + "\n";
        std::filesystem::remove_all(dir);
      }
  EXPECT_EQ(highRight, high) << rows;
  EXPECT_GE(2 * highRight, right) << rows;
  if (low >= 4) EXPECT_GE(10 * lowWrong, 7 * low) << rows;
}

// Real sections (../shared/data, skipped when absent), methods 1 and 2: OReX's eight (truth
// (1, 2, 0), met) is high; the hand (truth (1, 1, 0), met) is not low; OReX's Elephant (truth
// (1, 0, 0); 11 and 13 tunnels) and the mug (truth (1, 1, 0); 9 and 7) are low.
TEST(TopologyConfidence, RealSectionsAreRatedAsTheirResultsDeserve) {
  const std::filesystem::path data = std::filesystem::path(XSECT_SOURCE_DIR) / "../shared/data";
  struct RealSet {
    std::string name, input;
    std::vector<std::string> allowed;  ///< the levels the result deserves
  };
  const std::vector<RealSet> sets{{"eight", "csl: " + (data / "orex/eight_15.csl").string(), {"high"}},
                                  {"hand", "csl: " + (data / "orex/hand_ok.csl").string(), {"high", "medium"}},
                                  {"elephant", "csl: " + (data / "orex/Elephant.csl").string(), {"low"}},
                                  {"mug", "contour: " + (data / "contour/mug.contour").string(), {"low"}}};
  for (const RealSet& set : sets) {
    const std::string file = set.input.substr(set.input.find(' ') + 1);
    if (!std::filesystem::exists(file)) GTEST_SKIP() << "no " << file;
    for (const std::string method : {"nearest_plane", "section_voronoi"}) {
      const std::filesystem::path dir = test::freshDir("confidence-" + set.name);
      test::writeFile(dir / "config.yaml", "input:\n  " + set.input + "\nreconstruction:\n  method: " + method + "\n");
      const auto r = test::runXsect("run " + (dir / "config.yaml").string() + " --out " + (dir / "out").string() + " --quiet");
      ASSERT_EQ(r.code, 0) << r.err;
      const nlohmann::json rep = test::readJson(dir / "out/report.json");
      const std::string level = rep["topology"]["confidence"]["level"];
      EXPECT_NE(std::find(set.allowed.begin(), set.allowed.end(), level), set.allowed.end())
          << set.name << " " << method << ": " << rep["betti"].dump() << " " << rep["topology"]["confidence"]["text"];
      std::filesystem::remove_all(dir);
    }
  }
}

}  // namespace
}  // namespace xsect
