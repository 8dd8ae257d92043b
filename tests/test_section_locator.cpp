// Point location among a plane's sections (geometry/core/section_locator.h) must give exactly the
// brute-force answers of polygon.h: the first section whose sectionContains holds the point, and
// the distance to the nearest contour edge. Random star-shaped sections with holes and islands,
// overlapping sections, degenerate rings (two vertices, repeated vertices, collinear runs), and
// query points on a coarse lattice that the vertices share, so that rows through vertices,
// horizontal edges and points on edges are met often.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "geometry/core/polygon.h"
#include "geometry/core/section_locator.h"

using namespace xsect;

namespace {

/// A star-shaped ring about c: n vertices at radii in [r0, r1], snapped to a lattice of `snap` mm.
Ring starRing(std::mt19937& rng, const Vec2& c, double r0, double r1, int n, double snap, bool clockwise) {
  std::uniform_real_distribution<double> radius(r0, r1);
  Ring r;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * (clockwise ? n - k : k) / n;
    Vec2 p = c + radius(rng) * Vec2(std::cos(a), std::sin(a));
    p = (p / snap).array().round().matrix() * snap;
    r.push_back(p);
    if (k % 7 == 3) r.push_back(p);  // a repeated vertex
  }
  return r;
}

int firstHolding(const std::vector<Section>& sections, const Vec2& p) {
  for (std::size_t s = 0; s < sections.size(); ++s)
    if (!sections[s].outer.empty() && sectionContains(sections[s], p)) return int(s);
  return -1;
}

double nearestBrute(const std::vector<Section>& sections, const Vec2& p) {
  double d = std::numeric_limits<double>::infinity();
  for (const Section& s : sections) {
    if (s.outer.size() >= 2) d = std::min(d, ringDistance(s.outer, p));
    for (const Ring& h : s.holes)
      if (h.size() >= 2) d = std::min(d, ringDistance(h, p));
  }
  return d;
}

}  // namespace

TEST(SectionLocator, EqualsTheBruteForceAnswersOnRandomSections) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> centre(-40, 40), unit(0, 1);
  int held = 0, queries = 0;
  for (int config = 0; config < 60; ++config) {
    const double snap = config % 3 == 0 ? 1.0 : 1e-3;  // a coarse lattice: many ties
    std::vector<Section> sections;
    const int count = 1 + int(unit(rng) * 6);
    for (int s = 0; s < count; ++s) {
      Section sec;
      const Vec2 c(centre(rng), centre(rng));
      const int n = 3 + int(unit(rng) * 200);
      sec.outer = starRing(rng, c, 8, 20, n, snap, false);
      if (unit(rng) < 0.5) sec.holes.push_back(starRing(rng, c, 2, 6, 3 + int(unit(rng) * 40), snap, true));
      sections.push_back(sec);
      if (unit(rng) < 0.3) {  // an island inside the hole, or an overlapping copy
        Section island;
        island.outer = starRing(rng, c, 0.5, 1.5, 5, snap, false);
        sections.push_back(island);
      }
    }
    if (config % 10 == 5) sections.push_back(Section{Ring{Vec2(0, 0), Vec2(5, 5)}, {}, 1});  // two vertices
    if (config % 10 == 7) sections.push_back(Section{Ring{Vec2(-3, 1), Vec2(0, 1), Vec2(3, 1), Vec2(3, 4)}, {}, 1});
    const SectionLocator locator(sections);
    for (int q = 0; q < 3000; ++q) {
      Vec2 p(centre(rng) * 1.5, centre(rng) * 1.5);
      if (q % 2) p = (p / snap).array().round().matrix() * snap;  // on the vertices' lattice
      const int expected = firstHolding(sections, p);
      ASSERT_EQ(locator.holding(p), expected) << "config " << config << " point " << p.transpose();
      held += expected >= 0;
      ++queries;
      const SectionLocator::Nearest n = locator.nearestContour(p);
      EXPECT_NEAR(n.d, nearestBrute(sections, p), 1e-9);
      EXPECT_NEAR((n.q - p).norm(), n.d, 1e-9);
    }
  }
  EXPECT_GT(held, queries / 10);  // the test meets insides often
}

TEST(SectionLocator, NoSectionsHoldNothing) {
  const std::vector<Section> none;
  const SectionLocator locator(none);
  EXPECT_EQ(locator.holding(Vec2(0, 0)), -1);
  EXPECT_TRUE(std::isinf(locator.nearestContour(Vec2(0, 0)).d));
  EXPECT_TRUE(std::isinf(locator.boxBound(Vec2(0, 0))));
}

// More rings held at once than the slab scan's list keeps (64): 80 nested annuli, each a section
// whose hole holds the next one. A point near the centre lies inside every outer ring; the answer
// must still be the brute force's (the innermost section holding it, or none in a hole).
TEST(SectionLocator, ManyNestedSectionsAtOnceEqualTheBruteForce) {
  std::vector<Section> sections;
  const auto square = [](double h, bool clockwise) {
    Ring r{Vec2(-h, -h), Vec2(h, -h), Vec2(h, h), Vec2(-h, h)};
    if (clockwise) std::reverse(r.begin(), r.end());
    return r;
  };
  for (int k = 80; k >= 1; --k) sections.push_back(Section{square(k, false), {square(k - 0.5, true)}, 1});
  const SectionLocator locator(sections);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-81, 81);
  int held = 0;
  for (int q = 0; q < 4000; ++q) {
    const Vec2 p = q % 2 ? Vec2(u(rng), u(rng)) : Vec2(u(rng) / 40, u(rng) / 40);  // half near the centre
    const int expected = firstHolding(sections, p);
    ASSERT_EQ(locator.holding(p), expected) << p.transpose();
    held += expected >= 0;
  }
  EXPECT_GT(held, 500);
}
