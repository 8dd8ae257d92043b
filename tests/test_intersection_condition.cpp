// The Intersection Condition shown on the data (thesis ch. 1 §4.4; intersection_condition.h) on
// two-plane slabs whose lift(S_C) is known: contractible (overlapping discs; two discs joined by
// one bar) is shown; a piece with a hole (an annulus), a lift intersection in two components (a
// C-shaped section under a bar crossing both its arms) and a cycle of four pieces (two discs under
// two bars) are not.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/arrangement/connectivity_graph.h"
#include "geometry/arrangement/section_arrangement.h"
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

struct Slab {
  IntersectionConditionCheck check;
  bool slabShown = false;
};

/// Planes z = 0 and z = 1 holding `low` and `high`, closed by a box of half side 5.
Slab slab(const std::vector<Section>& low, const std::vector<Section>& high) {
  std::vector<CuttingPlane> planes(2);
  planes[0].plane = test::axisPlane(2, 0);
  planes[0].sections = low;
  planes[1].plane = test::axisPlane(2, 1);
  planes[1].sections = high;
  for (int axis = 0; axis < 3; ++axis)
    for (const double o : {-5.0, 5.0}) {
      CuttingPlane e;
      e.plane = test::axisPlane(axis, o);
      planes.push_back(e);
    }
  SectionScene scene;
  scene.planes = planes;
  scene.real_planes = 2;
  for (const CuttingPlane& p : planes) scene.fields.push_back(sectionDistanceField(p.sections, 0.05, 0.6));
  const SectionArrangement arr = arrangeSections(planes, 0.05);
  const ConnectivityGraphs g = connectivityGraphs(scene, arr, {}, false);
  Slab out;
  out.check = checkIntersectionCondition(planes, arr, g.lift_section, g.lift_length_mm);
  for (const SubSection& s : arr.sub_sections)
    if (s.plane == 0 && s.side == 1) out.slabShown = out.check.shown[std::size_t(s.cell)] != 0;
  return out;
}

}  // namespace

TEST(IntersectionCondition, ContractibleLiftsAreShown) {
  EXPECT_TRUE(slab({disc({0, 0}, 1)}, {disc({0.5, 0}, 1)}).slabShown);
  // Two discs joined by one bar: a tree of three pieces.
  EXPECT_TRUE(slab({disc({-1.5, 0}, 0.8), disc({1.5, 0}, 0.8)}, {rectangle({-2.5, 0.3}, {2.5, 0.7})}).slabShown);
}

TEST(IntersectionCondition, AHoleASplitIntersectionAndACycleAreNot) {
  Section annulus = disc({0, 0}, 2);
  annulus.holes.push_back(test::circle({0, 0}, 1, 96, false));
  const Slab hole = slab({annulus}, {disc({0, 0}, 2.5)});
  EXPECT_FALSE(hole.slabShown);
  EXPECT_GE(hole.check.cells_with_holes, 1);

  const Slab split = slab({cShape(1.4, 2, 20)}, {rectangle({-0.3, -2.5}, {0.3, 2.5})});
  EXPECT_FALSE(split.slabShown);
  EXPECT_GE(split.check.cells_with_cycles, 1);
  // The same bar across one arm only: one component.
  EXPECT_TRUE(slab({cShape(1.4, 2, 20)}, {rectangle({-0.3, 0.5}, {0.3, 2.5})}).slabShown);

  const Slab cycle = slab({disc({-1.5, 0}, 0.8), disc({1.5, 0}, 0.8)},
                          {rectangle({-2.5, 0.3}, {2.5, 0.7}), rectangle({-2.5, -0.7}, {2.5, -0.3})});
  EXPECT_FALSE(cycle.slabShown);
  EXPECT_GE(cycle.check.cells_with_cycles, 1);
}
