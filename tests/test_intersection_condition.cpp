// The Intersection Condition shown on the data (thesis ch. 1 §4.4; intersection_condition.h) on
// two-plane slabs whose R_C is known: contractible components (overlapping discs, two discs joined
// by one bar, an annulus under a disc, two separate discs) are shown; a tube (annuli on both
// planes), a C-shaped section under a bar crossing both its arms and two discs under two bars
// (loops) are not.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/sampling/intersection_condition.h"
#include "section_fixtures.h"

using namespace xsect;

namespace {

Section disc(const Vec2& c, double r) {
  Section s;
  s.outer = test::circle(c, r, 96);
  return s;
}

Section rectangle(const Vec2& lo, const Vec2& hi) {
  Section s;
  s.outer = {lo, Vec2(hi.x(), lo.y()), hi, Vec2(lo.x(), hi.y())};
  return s;
}

/// A C: the annulus r_in..r_out without the sector |angle| < gap (degrees), one simple polygon.
Section cShape(double rIn, double rOut, double gapDeg) {
  Section s;
  const double g = gapDeg * M_PI / 180;
  for (int i = 0; i <= 64; ++i) {
    const double a = g + (2 * M_PI - 2 * g) * i / 64;
    s.outer.push_back(rOut * Vec2(std::cos(a), std::sin(a)));
  }
  for (int i = 64; i >= 0; --i) {
    const double a = g + (2 * M_PI - 2 * g) * i / 64;
    s.outer.push_back(rIn * Vec2(std::cos(a), std::sin(a)));
  }
  return s;
}

/// Whether the Intersection Condition is shown in the slab cell between z = 0 (holding `low`) and
/// z = 1 (holding `high`), closed by a box of half side 2.5: R_C's components contractible.
CellReconstructionTopology slab(const std::vector<Section>& low, const std::vector<Section>& high,
                                double thickness = 1) {
  std::vector<Plane> planes = {test::axisPlane(2, 0), test::axisPlane(2, thickness)};
  std::vector<SectionDistanceField> fields = {sectionDistanceField(low, 0.02, 0.6), sectionDistanceField(high, 0.02, 0.6)};
  std::vector<int> sides = {1, -1};
  for (int axis = 0; axis < 3; ++axis)
    for (const double o : {-2.5, 2.5}) {
      planes.push_back(test::axisPlane(axis, o));
      fields.push_back(sectionDistanceField({}, 0.02, 0.6));
      sides.push_back(o < 0 ? 1 : -1);
    }
  CellTopologyParams p;
  p.max_spacing_mm = 0.05;
  return cellReconstructionTopology(planes, fields, sides, Vec3(0.1, 0.2, 0.5 * thickness), Vec3::Constant(-3),
                                    Vec3::Constant(3), p);
}

}  // namespace

TEST(IntersectionCondition, ContractibleReconstructionsAreShown) {
  const CellReconstructionTopology t = slab({disc({0, 0}, 1)}, {disc({0.5, 0}, 1)});
  EXPECT_TRUE(t.sampled);
  EXPECT_EQ(t.betti, (Betti{1, 0, 0}));
  EXPECT_TRUE(t.contractible());
  // Two discs joined by one bar: a tree.
  EXPECT_TRUE(slab({disc({-1.5, 0}, 0.8), disc({1.5, 0}, 0.8)}, {rectangle({-2.2, 0.3}, {2.2, 0.7})}).contractible());
  // An annulus under a disc: a cup, contractible although a piece has a hole.
  Section annulus = disc({0, 0}, 2);
  annulus.holes.push_back(test::circle({0, 0}, 1, 96, false));
  EXPECT_TRUE(slab({annulus}, {disc({0, 0}, 2)}).contractible());
  // Two separate discs over nothing: two components, each contractible.
  const CellReconstructionTopology two = slab({disc({-1.5, 0}, 0.8), disc({1.5, 0}, 0.8)}, {});
  EXPECT_EQ(two.betti, (Betti{2, 0, 0}));
  EXPECT_TRUE(two.contractible());
}

TEST(IntersectionCondition, LoopsThroughTheCellAreNot) {
  Section annulus = disc({0, 0}, 2);
  annulus.holes.push_back(test::circle({0, 0}, 1, 96, false));
  const CellReconstructionTopology tube = slab({annulus}, {annulus});
  EXPECT_EQ(tube.betti, (Betti{1, 1, 0}));
  EXPECT_FALSE(tube.contractible());
  // A C-shaped section under a bar crossing both its arms: the lifts meet twice, a loop.
  EXPECT_FALSE(slab({cShape(1.4, 2, 20)}, {rectangle({-0.3, -2.2}, {0.3, 2.2})}).contractible());
  EXPECT_TRUE(slab({cShape(1.4, 2, 20)}, {rectangle({-0.3, 0.5}, {0.3, 2.2})}).contractible());
  // A slab 50 times thinner than wide, the C's gap closed by a patch on the other plane: the lattice
  // keeps layers near both planes (no single layer on the bisector, where one plane would win).
  for (const double t : {1.0, 0.05}) {
    EXPECT_FALSE(slab({cShape(1.4, 2, 20)}, {rectangle({1.2, -0.8}, {2.2, 0.8})}, t).contractible()) << t;
    EXPECT_TRUE(slab({cShape(1.4, 2, 20)}, {rectangle({1.2, 0.2}, {2.2, 0.8})}, t).contractible()) << t;
  }
  // Two discs under two bars: a cycle of four pieces (thesis Fig. 1.11's torus).
  EXPECT_FALSE(slab({disc({-1.5, 0}, 0.8), disc({1.5, 0}, 0.8)},
                    {rectangle({-2.2, 0.3}, {2.2, 0.7}), rectangle({-2.2, -0.7}, {2.2, -0.3})})
                   .contractible());
}
