// The f_P raster (thesis ch. 1 §1.1: signed Euclidean distance to the section-contours, negative
// inside) against the exact distance to the polygons: exact at nodes within the band, bilinear
// between them, sign kept and magnitude clamped beyond the band.
#include <gtest/gtest.h>

#include <random>

#include "geometry/core/polygon.h"
#include "geometry/scene/section_distance_field.h"
#include "section_fixtures.h"

using namespace xsect;

TEST(SectionDistanceField, EqualsTheExactDistanceToThePolygons) {
  // an annulus (hole) plus an island inside its hole plus a separate square
  std::vector<Section> sections(3);
  sections[0].outer = test::circle(Vec2(5, 5), 8, 200);
  sections[0].holes.push_back(test::circle(Vec2(5, 5), 4, 120, false));
  sections[1].outer = test::circle(Vec2(5, 5), 1.5, 60);
  sections[2].outer = {Vec2(16, -3), Vec2(20, -3), Vec2(20, 1), Vec2(16, 1)};
  const double step = 0.1, band = 0.6;
  const SectionDistanceField f = sectionDistanceField(sections, step, band);
  ASSERT_GT(f.nu, 0);
  int checkedNodes = 0, checkedFar = 0;
  for (int j = 0; j < f.nv; j += 3)
    for (int i = 0; i < f.nu; i += 3) {
      const Vec2 p = f.origin + step * Vec2(i, j);
      const double exact = signedDistanceToSections(sections, p);
      const float got = f.node(i, j);
      if (std::abs(exact) < band) {
        EXPECT_NEAR(got, exact, 1e-5) << p.transpose();
        ++checkedNodes;
      } else {
        EXPECT_EQ(got, exact < 0 ? -f.band : f.band) << p.transpose();
        ++checkedFar;
      }
    }
  EXPECT_GT(checkedNodes, 500);
  EXPECT_GT(checkedFar, 500);
  // Between nodes: bilinear interpolation of a distance function, within step² of the exact value
  // wherever the segment to the nearest contour point is well inside the band.
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> ux(-4, 21), uy(-4, 14);
  int between = 0;
  for (int k = 0; k < 4000; ++k) {
    const Vec2 p(ux(rng), uy(rng));
    const double exact = signedDistanceToSections(sections, p);
    if (std::abs(exact) > 0.5 * band) continue;
    EXPECT_NEAR(f.sample(p.x(), p.y()), exact, step * step) << p.transpose();
    ++between;
  }
  EXPECT_GT(between, 200);
  // Far from every section (outside the raster), the plane holds nothing: +band.
  EXPECT_EQ(f.sample(100, 100), f.band);
  // An empty plane: no raster, +band everywhere.
  const SectionDistanceField empty = sectionDistanceField({}, step, band);
  EXPECT_EQ(empty.nu, 0);
  EXPECT_EQ(empty.sample(0, 0), empty.band);
}

// sampleWithGradient: the value of sample() and the derivative of the bilinear interpolant within
// the raster square (against a centred difference that stays inside the square), and the exact
// distance's gradient (a unit vector) near the contour; zero gradient where the value is ±band.
TEST(SectionDistanceField, GradientIsThatOfTheInterpolant) {
  std::vector<Section> sections(1);
  sections[0].outer = test::circle(Vec2(0, 0), 3, 300);
  const double step = 0.1, band = 0.6;
  const SectionDistanceField f = sectionDistanceField(sections, step, band);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-4, 4);
  int checked = 0, unit = 0;
  for (int k = 0; k < 3000; ++k) {
    const Vec2 p(u(rng), u(rng));
    Vec2 g;
    const float v = f.sampleWithGradient(p.x(), p.y(), &g);
    EXPECT_EQ(v, f.sample(p.x(), p.y()));
    if (std::abs(v) >= f.band) {
      EXPECT_EQ(g, Vec2::Zero());
      continue;
    }
    // A difference within the square holding p (h below the distance to its sides).
    const Vec2 x = (p - f.origin) / step;
    const double h = 0.25 * step * std::min({x.x() - std::floor(x.x()), std::ceil(x.x()) - x.x(),
                                             x.y() - std::floor(x.y()), std::ceil(x.y()) - x.y()});
    if (h < 1e-2 * step) continue;  // float values: a difference over less is noise
    const Vec2 d((f.sample(p.x() + h, p.y()) - f.sample(p.x() - h, p.y())) / (2 * h),
                 (f.sample(p.x(), p.y() + h) - f.sample(p.x(), p.y() - h)) / (2 * h));
    EXPECT_NEAR(g.x(), d.x(), 2e-3) << p.transpose();
    EXPECT_NEAR(g.y(), d.y(), 2e-3) << p.transpose();
    ++checked;
    if (std::abs(std::hypot(p.x(), p.y()) - 3) < 0.3) {
      EXPECT_NEAR(g.norm(), 1.0, 0.05) << p.transpose();
      ++unit;
    }
  }
  EXPECT_GT(checked, 300);
  EXPECT_GT(unit, 100);
}
