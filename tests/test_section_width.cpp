// A section's width (geometry/reconstruction/section_width.h): its inscribed disk's diameter.
#include <gtest/gtest.h>

#include "geometry/reconstruction/section_width.h"
#include "section_fixtures.h"

using namespace xsect;

TEST(SectionWidth, IsTheInscribedDiskDiameter) {
  // Within three raster steps, a step being the mean width 2A/P over 32 cells.
  Section disk;
  disk.outer = test::circle(Vec2(3, -2), 5.0, 256);
  EXPECT_NEAR(sectionWidth(disk), 10.0, 3 * 5.0 / 32);
  Section annulus = disk;
  annulus.holes = {test::circle(Vec2(3, -2), 3.0, 256, false)};
  EXPECT_NEAR(sectionWidth(annulus), 2.0, 3 * 2.0 / 32);
  for (const double w : {0.05, 0.5, 1.0, 2.0}) {
    Section strip;  // thin and long: the width, not the length, sets the raster
    strip.outer = {{0, 0}, {10, 0}, {10, w}, {0, w}};
    EXPECT_NEAR(sectionWidth(strip), w, 3 * w / 32 + 10.0 / 4096) << w;
  }
  Section empty;
  EXPECT_EQ(sectionWidth(empty), 0.0);
  EXPECT_THROW(sectionWidth(disk, 2), std::invalid_argument);
}
