// Contour pinning (contour_pinning.h): on a grid whose trilinear reading misses a contour because
// the field has a notch narrower than a voxel beside the plane, the voxels around the contour take
// the plane's own value, so the reading passes through the contour; nothing else changes.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "geometry/smoothing/contour_pinning.h"
#include "geometry/core/polygon.h"
#include "section_fixtures.h"

using namespace xsect;

namespace {

/// A disc of radius 2 on z = 0, and a field that is the disc's in-plane distance on the plane but
/// bulges 0.4 mm past it beside the plane: the solid meets the plane in the disc only within
/// 0.02 mm of it, a notch that no voxel centre (0.2 mm voxels, the plane between two layers) sees.
struct NotchScene {
  std::vector<CuttingPlane> planes;
  ScalarField field;
  NotchScene() {
    CuttingPlane c;
    c.plane = test::axisPlane(2, 0.0);
    c.sections.push_back(Section{test::circle(Vec2::Zero(), 2.0, 720), {}});
    planes.push_back(c);
    field.grid.voxel = 0.2;
    field.grid.origin = Vec3(-3.03, -3.01, -1.07);  // the plane lies between voxel centres
    field.grid.dims = {31, 31, 11};
    field.values.resize(std::size_t(field.grid.count()));
    for (int k = 0; k < 11; ++k)
      for (int j = 0; j < 31; ++j)
        for (int i = 0; i < 31; ++i) {
          const Vec3 x = field.grid.centre(i, j, k);
          const double r = std::hypot(x.x(), x.y()), notch = std::min(1.0, std::abs(x.z()) / 0.02);
          field.values[std::size_t(field.grid.index(i, j, k))] = float(r - 2.0 - 0.4 * notch);
        }
  }
  static double discValue(std::size_t, double a, double b) { return std::hypot(a, b) - 2.0; }
  /// Largest |trilinear reading| over points of the contour.
  double worstOnContour() const {
    double worst = 0;
    for (int a = 0; a < 360; ++a) {
      const double phi = 2 * M_PI * (a + 0.5) / 360;
      const Vec3 u = (Vec3(2 * std::cos(phi), 2 * std::sin(phi), 0) - field.grid.origin) / field.grid.voxel;
      const int i = int(std::floor(u.x())), j = int(std::floor(u.y())), k = int(std::floor(u.z()));
      double v = 0;
      for (int c = 0; c < 8; ++c) {
        const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
        v += (di ? u.x() - i : 1 - (u.x() - i)) * (dj ? u.y() - j : 1 - (u.y() - j)) *
             (dk ? u.z() - k : 1 - (u.z() - k)) * field.at(i + di, j + dj, k + dk);
      }
      worst = std::max(worst, std::abs(v));
    }
    return worst;
  }
};

}  // namespace

TEST(ContourPinning, PinsTheVoxelsAroundAMissedContourAndNothingElse) {
  NotchScene s;
  const ScalarField before = s.field;
  EXPECT_GT(s.worstOnContour(), 0.3);
  const ContourPinning p = pinSectionContours(s.field, s.planes, NotchScene::discValue, 0.05);
  EXPECT_GT(p.samples, 4 * 2 * M_PI * 2.0 / 0.2 - 10);  // a quarter voxel apart along the circle
  EXPECT_EQ(p.samples_pinned, p.samples);
  EXPECT_EQ(p.samples_outside + p.samples_crowded, 0);
  EXPECT_GT(p.worst_before_mm, 0.3);
  // The disc's distance is linear across the plane: trilinear reading error only (bilinear in r).
  EXPECT_LT(s.worstOnContour(), 0.01);
  // Changed: exactly the pinned voxels, all within one voxel of the plane and of the contour, each
  // holding the plane's value at its projection.
  std::int64_t changed = 0;
  for (int k = 0; k < 11; ++k)
    for (int j = 0; j < 31; ++j)
      for (int i = 0; i < 31; ++i) {
        if (s.field.at(i, j, k) == before.at(i, j, k)) continue;
        ++changed;
        const Vec3 x = s.field.grid.centre(i, j, k);
        EXPECT_LT(std::abs(x.z()), 0.2);
        EXPECT_LT(std::abs(std::hypot(x.x(), x.y()) - 2.0), 0.2 * std::sqrt(2.0) + 1e-9);
        EXPECT_FLOAT_EQ(s.field.at(i, j, k), float(std::hypot(x.x(), x.y()) - 2.0));
      }
  EXPECT_EQ(changed, p.voxels_pinned);
  // A field that already passes through the contour is left alone.
  const ScalarField pinned = s.field;
  const ContourPinning again = pinSectionContours(s.field, s.planes, NotchScene::discValue, 0.05);
  EXPECT_EQ(again.samples_pinned, 0);
  EXPECT_EQ(again.voxels_pinned, 0);
  EXPECT_EQ(s.field.values, pinned.values);
}

TEST(ContourPinning, LeavesASolidThatMissesTheContourAndPlanesCloserThanAVoxel) {
  // A field 0.4 mm outside the disc's: pinning the rim would leave a ring of inside voxels around
  // an outside middle (a hole); it is counted, not pinned.
  NotchScene s;
  for (float& v : s.field.values) v += 0.8f;
  const ScalarField before = s.field;
  const ContourPinning p = pinSectionContours(s.field, s.planes, NotchScene::discValue, 0.05);
  EXPECT_EQ(p.samples_outside, p.samples);
  EXPECT_EQ(p.voxels_pinned, 0);
  EXPECT_EQ(s.field.values, before.values);
  // A second disc 0.1 mm above the first: the grid cannot hold both contours, nothing is pinned.
  NotchScene t;
  CuttingPlane c;
  c.plane = test::axisPlane(2, 0.1);
  c.sections.push_back(Section{test::circle(Vec2::Zero(), 2.3, 720), {}});
  t.planes.push_back(c);
  const ScalarField tb = t.field;
  const ContourPinning q = pinSectionContours(t.field, t.planes, NotchScene::discValue, 0.05);
  EXPECT_EQ(q.samples_crowded, q.samples);
  EXPECT_EQ(t.field.values, tb.values);
}

TEST(ContourPinning, AVoxelTakesTheNearestAskingPlanesValue) {
  // Two discs 0.5 mm apart (more than a voxel), both bulged past: voxels nearer the upper plane
  // take its value, whatever the planes' order.
  for (const bool upperFirst : {false, true}) {
    NotchScene s;
    CuttingPlane c;
    c.plane = test::axisPlane(2, 0.5);
    c.sections.push_back(Section{test::circle(Vec2::Zero(), 2.0, 720), {}});
    if (upperFirst) s.planes.insert(s.planes.begin(), c);
    else s.planes.push_back(c);
    const auto value = [&](std::size_t i, double a, double b) {
      return std::hypot(a, b) - 2.0 + (std::abs(s.planes[i].plane.origin.z()) > 0.25 ? 0.01 : 0.0);
    };
    const ScalarField before = s.field;
    const ContourPinning p = pinSectionContours(s.field, s.planes, value, 0.05);
    EXPECT_GT(p.voxels_pinned, 0);
    for (int k = 0; k < 11; ++k)
      for (int j = 0; j < 31; ++j)
        for (int i = 0; i < 31; ++i) {
          if (s.field.at(i, j, k) == before.at(i, j, k)) continue;
          const Vec3 x = s.field.grid.centre(i, j, k);
          const double r = std::hypot(x.x(), x.y()) - 2.0;
          EXPECT_FLOAT_EQ(s.field.at(i, j, k), float(r + (std::abs(x.z() - 0.5) < std::abs(x.z()) ? 0.01 : 0.0)))
              << x.transpose();
        }
  }
}

TEST(ContourPinning, SamplesEveryRingAtMostAStepApart) {
  // The samples pinning reads (polygon.h contourSamples): a unit square with a square hole.
  const Ring outer{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, hole{{0.4, 0.4}, {0.4, 0.6}, {0.6, 0.6}, {0.6, 0.4}};
  const std::vector<Section> sections{Section{outer, {hole}}};
  const std::vector<Vec2> s = contourSamples(sections, 0.3);
  EXPECT_EQ(s.size(), 4u * 4u + 4u * 1u);  // ceil(1 / 0.3) = 4 per outer edge, 1 per 0.2 edge
  EXPECT_EQ(s[0], Vec2(0, 0));
  EXPECT_EQ(s[1], Vec2(0.25, 0));
  EXPECT_EQ(s[16], Vec2(0.4, 0.4));
  EXPECT_EQ(contourSamples(sections, std::numeric_limits<double>::infinity()).size(), 8u);
  NotchScene n;
  EXPECT_EQ(pinSectionContours(n.field, n.planes, NotchScene::discValue, 0.05).samples, 720);
}

TEST(ContourPinning, RejectsInvalidArguments) {
  NotchScene s;
  EXPECT_THROW(pinSectionContours(s.field, s.planes, NotchScene::discValue, -1.0), std::invalid_argument);
  s.field.values.pop_back();
  EXPECT_THROW(pinSectionContours(s.field, s.planes, NotchScene::discValue, 0.1), std::invalid_argument);
}
