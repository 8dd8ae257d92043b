// The elevation median of a sweep (segmentation/elevation_median.h): what one frame of three saw
// alone goes, a surface monotone through the frames keeps its contours, far or tilted neighbours
// do not vote.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/core/polygon.h"
#include "section_fixtures.h"
#include "segmentation/elevation_median.h"

namespace xsect {
namespace {

using test::observedPlane;
using test::shellSections;

constexpr double kRadius = 5.0;   // the ball swept, mm
constexpr double kPixel = 0.1;    // the frames' pixel, mm

/// A sweep of `count` frames at `spacing` along z through the ball of kRadius at the origin, each
/// tilted about x by `tilt_deg` times its index (a freehand sweep's slow rotation), observed over
/// [-8, 8]² mm.
std::vector<CuttingPlane> sweep(int count, double spacing, double tilt_deg) {
  std::vector<CuttingPlane> planes;
  for (int k = 0; k < count; ++k) {
    const double z = (k - (count - 1) / 2.0) * spacing;
    const double a = tilt_deg * M_PI / 180.0 * (k - (count - 1) / 2.0);
    Plane p;
    p.normal = Vec3(0, -std::sin(a), std::cos(a));
    p.u = Vec3::UnitX();
    p.v = p.normal.cross(p.u);
    p.origin = Vec3(0, 0, z);
    p.origin -= p.u * 8.0 + p.v * 8.0;  // plane coordinates from the image's corner
    planes.push_back(observedPlane(p, shellSections(p, Vec3::Zero(), kRadius, 0.0, 512),
                                   PlaneRect{Vec2::Zero(), Vec2(16, 16)}, kPixel, k, false));
  }
  return planes;
}

/// The largest distance from a vertex of the plane's sections to the ball's surface (mm).
double worstDeviation(const CuttingPlane& cp) {
  double worst = 0;
  for (const Section& s : cp.sections)
    for (const Vec2& q : s.outer) worst = std::max(worst, std::abs(cp.plane.toWorld(q).norm() - kRadius));
  return worst;
}

/// The ball's section of `cp` with a bump of `height` mm (outward > 0, a notch < 0) around the
/// in-plane direction `angle`, `width` radians wide.
void addBump(CuttingPlane& cp, double angle, double width, double height) {
  const Vec2 c = cp.plane.toPlane(Vec3::Zero());
  for (Ring* ring : {&cp.sections.front().outer}) {
    for (Vec2& q : *ring) {
      const Vec2 d = q - c;
      double delta = std::remainder(std::atan2(d.y(), d.x()) - angle, 2 * M_PI);
      const double w = std::abs(delta) < width ? std::pow(std::cos(delta / width * M_PI / 2), 2) : 0.0;
      q = c + d * (1.0 + height * w / d.norm());
    }
  }
}

/// What the median may cost a frame of the sweep `truth` (unbumped): where the frame's own value is
/// the odd one out it takes a neighbour's, so each point lies on the frame's own or a neighbour's
/// true contour projected on it: the farthest such projection from the ball's surface (s²/2R at the
/// equator, the surface's shift over one frame on its slopes), plus the raster's tracing error.
double allowance(const std::vector<CuttingPlane>& truth, std::size_t k) {
  double worst = 0;
  for (const std::size_t j : {k - 1, k + 1})
    for (const Vec2& q : truth[j].sections.front().outer) {
      const Vec3 x = truth[k].plane.toWorld(truth[k].plane.toPlane(truth[j].plane.toWorld(q)));
      worst = std::max(worst, std::abs(x.norm() - kRadius));
    }
  return worst + 0.5 * kPixel;
}

TEST(ElevationMedian, WhatOneFrameSawAloneGoesOnRandomSweeps) {
  std::mt19937_64 rng(49);
  std::uniform_real_distribution<double> u01(0, 1);
  for (int trial = 0; trial < 40; ++trial) {
    const double spacing = 0.3 + 0.4 * u01(rng);  // within the 1 mm at every node of the tilted frames
    const std::vector<CuttingPlane> truth = sweep(9, spacing, 3.0 * (u01(rng) - 0.5));
    std::vector<CuttingPlane> planes = truth;
    // One frame near the middle bulges (speckle joined to the lumen), another is notched.
    const int bulged = 2 + int(u01(rng) * 5), notched = bulged == 4 ? 5 : 4;
    const double height = 0.5 + 2.0 * u01(rng);
    addBump(planes[std::size_t(bulged)], 2 * M_PI * u01(rng), 0.3 + 0.5 * u01(rng), height);
    addBump(planes[std::size_t(notched)], 2 * M_PI * u01(rng), 0.3 + 0.5 * u01(rng), -0.8 * height);
    ASSERT_GT(worstDeviation(planes[std::size_t(bulged)]), 0.45) << trial;
    const ElevationMedian m = elevationMedian(planes, 1.0);
    ASSERT_EQ(m.planes.size(), planes.size());
    EXPECT_GE(m.frames_changed, 2) << trial;
    EXPECT_GT(m.area_removed_mm2, 0) << trial;
    EXPECT_GT(m.area_added_mm2, 0) << trial;
    for (std::size_t k = 1; k + 1 < planes.size(); ++k)
      EXPECT_LE(worstDeviation(m.planes[k]), allowance(truth, k)) << "trial " << trial << ", frame " << k;
    // The first and last frames have one neighbour: kept as they are.
    EXPECT_EQ(m.planes.front().sections.front().outer, planes.front().sections.front().outer);
    EXPECT_EQ(m.planes.back().sections.front().outer, planes.back().sections.front().outer);
  }
}

TEST(ElevationMedian, ASurfaceMonotoneThroughTheFramesKeepsItsContours) {
  // Frames on one side of the ball's equator: the sections shrink monotonically, so no frame's
  // region changes and every contour is kept as it was, vertex for vertex.
  std::vector<CuttingPlane> planes = sweep(9, 0.5, 0.0);
  for (CuttingPlane& cp : planes) {
    cp.plane.origin.z() += 2.5;
    cp.sections = shellSections(cp.plane, Vec3::Zero(), kRadius, 0.0, 512);
  }
  const ElevationMedian m = elevationMedian(planes, 1.0);
  EXPECT_EQ(m.frames_changed, 0);
  for (std::size_t k = 0; k < planes.size(); ++k)
    EXPECT_EQ(m.planes[k].sections.front().outer, planes[k].sections.front().outer) << k;
}

TEST(ElevationMedian, ASpeckSeenByOneFrameGoesSeenByTwoStays) {
  std::vector<CuttingPlane> planes = sweep(7, 0.5, 0.0);
  Section speck;
  speck.outer = test::circle(Vec2(14.5, 14.5), 0.6, 64);  // far from the ball's sections
  planes[3].sections.push_back(speck);
  ElevationMedian m = elevationMedian(planes, 1.0);
  for (const CuttingPlane& cp : m.planes) EXPECT_EQ(cp.sections.size(), 1u);
  planes[4].sections.push_back(speck);  // a structure two frames thick: a majority of frames 3-5
  m = elevationMedian(planes, 1.0);
  EXPECT_EQ(m.planes[3].sections.size(), 2u);
  EXPECT_EQ(m.planes[4].sections.size(), 2u);
  for (const Section& s : m.planes[3].sections)  // the speck's two frames agree: kept as seen
    if (sectionCentroid(s).x() > 13) EXPECT_NEAR(sectionArea(s), sectionArea(speck), 0.02);
}

TEST(ElevationMedian, FarTiltedOrUnobservingNeighboursDoNotVote) {
  // Frames 2 mm apart: farther than the 1 mm the beam's slab is taken to be.
  std::vector<CuttingPlane> planes = sweep(5, 2.0, 0.0);
  addBump(planes[2], 0.5, 0.5, 1.5);
  EXPECT_EQ(elevationMedian(planes, 1.0).frames_changed, 0);
  EXPECT_GT(elevationMedian(planes, 2.5).frames_changed, 0);  // within the distance given: they do
  // Neighbours 0.5 mm away but turned by 30°: another view of the object, not the same slab.
  std::vector<CuttingPlane> tilted = sweep(3, 0.5, 30.0);
  addBump(tilted[1], 0.5, 0.5, 1.5);
  EXPECT_EQ(elevationMedian(tilted, 1.0).frames_changed, 0);
  // A neighbour that did not observe where the bulge is (its image ends at u = 8 mm).
  std::vector<CuttingPlane> cut = sweep(3, 0.5, 0.0);
  addBump(cut[1], 0.0, 0.5, 1.5);  // towards +u
  cut[2].extent.max.x() = 8.0 + 4.0;
  const ElevationMedian m = elevationMedian(cut, 1.0);
  EXPECT_GT(worstDeviation(m.planes[1]), 1.0);
}

}  // namespace
}  // namespace xsect
