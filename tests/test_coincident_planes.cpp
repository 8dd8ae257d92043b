// Issue 15: observations of one plane become one plane with the consensus of their sections
// (segmentation/coincident_consensus.h). The consensus of two concentric disks of radii 3 and 5 is
// the disk of radius 4 (the mean of their signed distances vanishes halfway); their disagreement
// is the annulus between them, and each contour moves by 1 mm. Members whose planes carry other
// (u, v) frames are read through the world; the merged plane observes the union of their regions.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/arrangement/coincident_planes.h"
#include "geometry/core/polygon.h"
#include "section_fixtures.h"
#include "segmentation/coincident_consensus.h"

using namespace xsect;

namespace {

const double kPi = std::acos(-1.0);

/// A 0.05 mm-pixel observation of the plane z = z0 holding a disk of radius r centred at world (cx, cy),
/// in a frame turned by `turn` radians about z and with its origin at world (ox, oy, z0).
CuttingPlane diskObservation(int slice, double r, double cx, double cy, double turn, double ox, double oy,
                             double z0 = 0.0) {
  CuttingPlane p;
  p.slice = slice;
  p.name = "obs" + std::to_string(slice);
  p.plane.origin = Vec3(ox, oy, z0);
  p.plane.u = Vec3(std::cos(turn), std::sin(turn), 0);
  p.plane.v = Vec3(-std::sin(turn), std::cos(turn), 0);
  p.plane.normal = Vec3::UnitZ();
  p.pixel_mm = 0.05;
  const Vec2 c = p.plane.toPlane(Vec3(cx, cy, z0));
  p.sections.push_back(Section{test::circle(c, r, 400), {}, 1});
  p.extent = {c - Vec2(10, 10), c + Vec2(10, 10)};  // a 20 mm image around the disk, in its own frame
  return p;
}

}  // namespace

TEST(CoincidentPlanes, DetectedWithinAThousandthOfAPixelOnly) {
  const CuttingPlane a = diskObservation(0, 3, 0, 0, 0, -10, -10);
  EXPECT_TRUE(planesCoincide(a, diskObservation(1, 5, 0, 0, 0.7, 3, -2, 4e-5)));   // < 5e-5 mm
  EXPECT_FALSE(planesCoincide(a, diskObservation(1, 5, 0, 0, 0.7, 3, -2, 6e-5)));  // > 5e-5 mm
  CuttingPlane flipped = diskObservation(1, 5, 0, 0, 0, -10, -10);
  std::swap(flipped.plane.u, flipped.plane.v);  // the same plane seen from the other side
  flipped.plane.normal = -flipped.plane.normal;
  EXPECT_TRUE(planesCoincide(a, flipped));
  CuttingPlane tilted = diskObservation(1, 5, 0, 0, 0, -10, -10);
  tilted.plane.normal = Vec3(1e-5, 0, 1).normalized();  // 0.0006°: 1e-4 mm over the 20 mm extent
  tilted.plane.u = tilted.plane.v.cross(tilted.plane.normal);
  EXPECT_FALSE(planesCoincide(a, tilted));
  CuttingPlane virtualPlane = a, unobserved = a;
  virtualPlane.is_virtual = true;
  unobserved.extent = PlaneRect{};  // a field-of-view mask with no observed pixel
  EXPECT_FALSE(planesCoincide(a, virtualPlane));
  EXPECT_FALSE(planesCoincide(a, unobserved));
  const std::vector<CoincidentGroup> groups =
      coincidentGroups({a, diskObservation(1, 4, 0, 0, 0, 0, 0, 5.0), diskObservation(2, 5, 0, 0, 1.0, 2, 2),
                        diskObservation(3, 4, 0, 0, 0, 0, 0, 5.00001), diskObservation(4, 4, 0, 0, 0, 0, 0, 5.01)});
  ASSERT_EQ(groups.size(), 2u);
  EXPECT_EQ(groups[0].members, (std::vector<std::size_t>{0, 2}));
  EXPECT_EQ(groups[1].members, (std::vector<std::size_t>{1, 3}));
}

TEST(CoincidentPlanes, ConsensusOfTwoDisksIsTheMeanDisk) {
  // Radii 3 and 5, the second in a frame turned by 40° with another origin; a third plane elsewhere.
  std::vector<CuttingPlane> planes = {diskObservation(0, 3, 1, 2, 0, -10, -10),
                                      diskObservation(7, 2, 0, 0, 0, -10, -10, 6.0),
                                      diskObservation(4, 5, 1, 2, 40 * kPi / 180, 4, -3)};
  const CoincidentMerge m = mergeCoincidentPlanes(planes, {});
  ASSERT_EQ(m.planes.size(), 2u);
  ASSERT_EQ(m.consensus.size(), 1u);
  EXPECT_EQ(m.consensus[0].slices, (std::vector<int>{0, 4}));
  EXPECT_EQ(m.planes[0].slice, 0);
  EXPECT_EQ(m.planes[1].slice, 7);
  ASSERT_EQ(m.planes[0].sections.size(), 1u);
  const Section& s = m.planes[0].sections[0];
  EXPECT_TRUE(s.holes.empty());
  EXPECT_NEAR(sectionArea(s), kPi * 16, 0.01 * kPi * 16);
  for (const Vec2& p : s.outer) EXPECT_NEAR((m.planes[0].plane.toWorld(p) - Vec3(1, 2, 0)).norm(), 4.0, 0.05);
  EXPECT_NEAR(m.consensus[0].disagreement_area_mm2, kPi * (25 - 9), 0.02 * kPi * 16);
  EXPECT_NEAR(m.consensus[0].max_correction_mm, 1.0, 0.06);
  EXPECT_FALSE(m.planes[0].field_of_view.empty());  // the union of two turned squares
}

TEST(CoincidentPlanes, TheMedianOfThreeIgnoresTheOddOneAndAMissedSectionErasesNothing) {
  // Radii 3, 5 and 9: the median distance is the middle disk's, whatever the outlier says.
  std::vector<CuttingPlane> three = {diskObservation(0, 3, 0, 0, 0, -10, -10), diskObservation(1, 9, 0, 0, 0.3, -10, -10),
                                     diskObservation(2, 5, 0, 0, 2.0, 1, 1)};
  CoincidentMerge m = mergeCoincidentPlanes(three, {});
  ASSERT_EQ(m.planes.size(), 1u);
  ASSERT_EQ(m.planes[0].sections.size(), 1u);
  EXPECT_NEAR(sectionArea(m.planes[0].sections[0]), kPi * 25, 0.01 * kPi * 25);
  EXPECT_EQ(m.consensus[0].voting, 3);
  // Two observations, one without the section (a missed segmentation): the section stays.
  CuttingPlane blank = diskObservation(1, 4, 0, 0, 0, -10, -10);
  blank.sections.clear();
  m = mergeCoincidentPlanes({diskObservation(0, 4, 0, 0, 0, -10, -10), blank}, {});
  ASSERT_EQ(m.planes[0].sections.size(), 1u);
  EXPECT_NEAR(sectionArea(m.planes[0].sections[0]), kPi * 16, 0.01 * kPi * 16);
  EXPECT_EQ(m.consensus[0].voting, 1);
}

TEST(CoincidentPlanes, FarFromBothContoursTheDistancesStillDecide) {
  // A disk of radius 10 and the same disk with a lumen of radius 9: halfway between them the lumen
  // is still inside (the mean distance there is -0.5 mm everywhere), however far from both
  // contours a point of the lumen lies. Clamped distances would open a false hole.
  CuttingPlane disk = diskObservation(0, 10, 0, 0, 0, -15, -15), ring = diskObservation(1, 10, 0, 0, 0, -15, -15);
  disk.extent = ring.extent = {Vec2(0, 0), Vec2(30, 30)};
  ring.sections[0].holes.push_back(test::circle(Vec2(15, 15), 9, 400, false));
  const CoincidentMerge m = mergeCoincidentPlanes({disk, ring}, {});
  ASSERT_EQ(m.planes[0].sections.size(), 1u);
  EXPECT_TRUE(m.planes[0].sections[0].holes.empty());
  EXPECT_NEAR(sectionArea(m.planes[0].sections[0]), kPi * 100, 0.01 * kPi * 100);
  EXPECT_NEAR(m.consensus[0].disagreement_area_mm2, kPi * 81, 0.02 * kPi * 81);
}

TEST(CoincidentPlanes, ContourPlanesListedTwiceUniteTheirContours) {
  // A .csl listing one plane twice with a disk each (contours given directly, observed everywhere).
  CuttingPlane a = diskObservation(0, 2, -5, 0, 0, -10, -10), b = diskObservation(1, 2, 5, 0, 0, -10, -10);
  for (CuttingPlane* p : {&a, &b}) {
    p->pixel_mm = 0;
    p->observed_everywhere = true;
    p->extent = {ringBounds(p->sections[0].outer).min(), ringBounds(p->sections[0].outer).max()};
  }
  // Their extents (the sections' bounds) differ; the planes are still one.
  const CoincidentMerge m = mergeCoincidentPlanes({a, b}, {});
  ASSERT_EQ(m.planes.size(), 1u);
  ASSERT_EQ(m.planes[0].sections.size(), 2u);
  for (const Section& s : m.planes[0].sections) EXPECT_NEAR(sectionArea(s), kPi * 4, 0.02 * kPi * 4);
  EXPECT_NEAR(m.planes[0].extent.max.x() - m.planes[0].extent.min.x(), 14.0, 0.05);
}

TEST(CoincidentPlanes, LabelledSectionsTileTheConsensus) {
  // Two observations of a disk split into label 1 (x < 0) and label 2 (x > 0), the second with the
  // split moved to x = 1: the labels' consensus splits at x = 0.5, and the labels tile the union.
  const auto halves = [](double split) {
    Section left{{Vec2(-4 + 10, -4 + 10), Vec2(split + 10, -4 + 10), Vec2(split + 10, 4 + 10), Vec2(-4 + 10, 4 + 10)}, {}, 1};
    Section right{{Vec2(split + 10, -4 + 10), Vec2(4 + 10, -4 + 10), Vec2(4 + 10, 4 + 10), Vec2(split + 10, 4 + 10)}, {}, 2};
    return std::vector<Section>{left, right};
  };
  CuttingPlane a = diskObservation(0, 4, 0, 0, 0, -10, -10), b = diskObservation(1, 4, 0, 0, 0, -10, -10);
  Section square{{Vec2(6, 6), Vec2(14, 6), Vec2(14, 14), Vec2(6, 14)}, {}, 1};
  a.sections = b.sections = {square};
  const CoincidentMerge m = mergeCoincidentPlanes({a, b}, {halves(0.0), halves(1.0)});
  ASSERT_EQ(m.labelled.size(), 1u);
  double area1 = 0, area2 = 0;
  for (const Section& s : m.labelled[0]) (s.label == 1 ? area1 : area2) += sectionArea(s);
  EXPECT_NEAR(area1, 8 * 4.5, 0.3);
  EXPECT_NEAR(area2, 8 * 3.5, 0.3);
  double total = 0;
  for (const Section& s : m.planes[0].sections) total += sectionArea(s);
  EXPECT_NEAR(area1 + area2, total, 0.05);
  EXPECT_NEAR(total, 64, 0.3);
}

TEST(CoincidentPlanes, AgreeingObservationsKeepTheirSectionAndTheMergedPlaneObservesTheUnion) {
  CuttingPlane a = diskObservation(0, 3, 0, 0, 0, -10, -10), b = diskObservation(1, 3, 0, 0, 0, -10, -10);
  const CoincidentMerge same = mergeCoincidentPlanes({a, b}, {});
  EXPECT_TRUE(same.planes[0].field_of_view.empty());  // both observed the same 20 mm square
  b.extent = {Vec2(10, 10), Vec2(25, 25)};  // b saw x, y in [0, 15]: the union is not a rectangle
  const CoincidentMerge m = mergeCoincidentPlanes({a, b}, {});
  ASSERT_EQ(m.planes.size(), 1u);
  EXPECT_EQ(m.consensus[0].disagreement_area_mm2, 0.0);
  EXPECT_EQ(m.consensus[0].max_correction_mm, 0.0);
  ASSERT_EQ(m.planes[0].sections.size(), 1u);
  EXPECT_EQ(m.planes[0].sections[0].outer, a.sections[0].outer);  // kept as they are
  const CuttingPlane& p = m.planes[0];
  EXPECT_NEAR(p.extent.max.x(), 25.0, 1e-9);
  ASSERT_FALSE(p.field_of_view.empty());
  const auto seen = [&](double x, double y) {
    bool in = false;
    for (const Ring& r : p.field_of_view) in ^= ringContains(r, p.plane.toPlane(Vec3(x, y, 0)));
    return in;
  };
  EXPECT_TRUE(seen(-5, -5));
  EXPECT_TRUE(seen(12, 12));
  EXPECT_FALSE(seen(12, -5));
  EXPECT_FALSE(seen(-5, 12));
}

TEST(CoincidentPlanes, LabelsAreVotedByEveryObservation) {
  // Three observations of one square: two say label 2, one says label 3. Label 2 wins everywhere.
  CuttingPlane a = diskObservation(0, 4, 0, 0, 0, -10, -10);
  Section square{{Vec2(6, 6), Vec2(14, 6), Vec2(14, 14), Vec2(6, 14)}, {}, 1};
  a.sections = {square};
  std::vector<CuttingPlane> planes = {a, a, a};
  planes[1].slice = 1;
  planes[2].slice = 2;
  Section two = square, three = square;
  two.label = 2;
  three.label = 3;
  const CoincidentMerge m = mergeCoincidentPlanes(planes, {{two}, {three}, {two}});
  ASSERT_EQ(m.labelled.size(), 1u);
  double area2 = 0, area3 = 0;
  for (const Section& s : m.labelled[0]) (s.label == 2 ? area2 : area3) += sectionArea(s);
  EXPECT_NEAR(area2, 64, 0.3);
  EXPECT_NEAR(area3, 0, 1e-9);
}

TEST(CoincidentPlanes, AnObservationFromTheOtherSideKeepsItsOrientation) {
  // The first observation holds nothing; the second, of the same plane seen from the other side
  // (normal reversed, u and v swapped), holds a disk: kept as it is, counter-clockwise in the
  // first observation's frame.
  CuttingPlane empty = diskObservation(0, 3, 0, 0, 0, -10, -10), flipped = diskObservation(1, 3, 0, 0, 0, -10, -10);
  empty.sections.clear();
  std::swap(flipped.plane.u, flipped.plane.v);
  flipped.plane.normal = -flipped.plane.normal;
  flipped.sections = {Section{test::circle(Vec2(10, 10), 3, 400), {}, 1}};
  flipped.extent = {Vec2(0, 0), Vec2(20, 20)};
  const CoincidentMerge m = mergeCoincidentPlanes({empty, flipped}, {});
  ASSERT_EQ(m.planes[0].sections.size(), 1u);
  EXPECT_GT(signedArea(m.planes[0].sections[0].outer), 0.0);
  EXPECT_NEAR(sectionArea(m.planes[0].sections[0]), kPi * 9, 0.01 * kPi * 9);
  EXPECT_EQ(m.consensus[0].rule, "identical");
}
