// Issue 16: choices are enums parsed once where the YAML is read. Every table names each value
// once, its names read back to the value, and a configuration naming anything else is refused with
// the list of names (exit 2, naming the key).
#include <gtest/gtest.h>

#include <set>

#include "cli.h"
#include "geometry/phantoms/phantom_shape.h"
#include "geometry/phantoms/slicing_pattern.h"
#include "io/run_config.h"

using namespace xsect;

namespace {

template <typename E, std::size_t N>
void expectRoundTrip(const std::array<NamedChoice<E>, N>& table) {
  std::set<std::string> names;
  std::set<int> values;
  for (const NamedChoice<E>& c : table) {
    EXPECT_TRUE(names.insert(c.name).second) << c.name;
    EXPECT_TRUE(values.insert(int(c.value)).second) << c.name;
    EXPECT_EQ(choiceNamed(table, c.name), c.value);
    EXPECT_STREQ(nameOf(table, c.value), c.name);
  }
  EXPECT_FALSE(choiceNamed(table, "no such choice").has_value());
}

}  // namespace

TEST(NamedChoices, EveryTableRoundTrips) {
  expectRoundTrip(kInputKinds);
  expectRoundTrip(kSmoothingMethods);
  expectRoundTrip(kReconstructionMethods);
  expectRoundTrip(kConsensusModes);
  expectRoundTrip(kPoseCorrectionKinds);
  expectRoundTrip(kSegmentationMethods);
  expectRoundTrip(kSegmentationPresets);
  expectRoundTrip(kInsideSides);
  expectRoundTrip(kShadowRules);
  expectRoundTrip(kShapeKinds);
  expectRoundTrip(kPatternKinds);
  EXPECT_EQ(choiceNames(kSmoothingMethods), "none | shepard | level_set");
}

TEST(NamedChoices, AnUnknownChoiceIsRefusedWithTheNames) {
  const auto dir = test::freshDir("named_choices");
  test::writeFile(dir / "s.csl", "CSLC\n1 1\n1 3 1 0 0 1 0\n0 0 0\n1 0 0\n0 1 0\n3 1 0 1 2\n");
  test::writeFile(dir / "c.yaml", "input: {csl: s.csl}\n");
  const struct { const char* set; const char* says; } cases[] = {
      {"smoothing.method=gauss", "--set smoothing.method=gauss: unknown method 'gauss' (none | shepard | level_set)"},
      {"reconstruction.method=poisson", "--set reconstruction.method=poisson: unknown method 'poisson' (nearest_plane | section_voronoi | delaunay)"},
      {"conformity.mode=mean", "--set conformity.mode=mean: unknown mode 'mean' (intersection | union | average)"},
      {"segmentation.method=kmeans", "--set segmentation.method=kmeans: unknown method 'kmeans' (threshold | otsu | min_error | labels)"},
      {"segmentation.inside=dark", "--set segmentation.inside=dark: unknown side 'dark' (above | below | auto)"},
  };
  for (const auto& c : cases) {
    const auto r = test::runXsect("check " + (dir / "c.yaml").string() + " --set " + c.set);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
  }
  std::filesystem::remove_all(dir);
}
