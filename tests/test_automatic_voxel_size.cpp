// Issue 14, "scale-free defaults": an automatic voxel size that scales with the data whatever their
// unit, follows thin sections, and is rounded to two significant digits.
#include <gtest/gtest.h>

#include "geometry/reconstruction/automatic_voxel_size.h"
#include "geometry/reconstruction/section_width.h"
#include "section_fixtures.h"

using namespace xsect;

TEST(AutomaticVoxelSize, ScalesWithTheDataWhateverTheirUnit) {
  // Sections of a ball cut by three stacks, in units from 10^-3 to 10^3: the voxel size scales
  // with the data (to two significant digits) and the grid stays the same size.
  const auto scene = [](double scale) {
    std::vector<CuttingPlane> planes;
    for (int axis = 0; axis < 3; ++axis)
      for (int q = -3; q <= 3; ++q) {
        CuttingPlane p;
        p.plane = test::axisPlane(axis, scale * 1.7 * q);
        p.plane.origin += scale * Vec3(0.3, -0.2, 0.1);
        p.sections = test::shellSections(p.plane, scale * Vec3(0.3, -0.2, 0.1), scale * 6.0, 0.0);
        planes.push_back(p);
      }
    return planes;
  };
  const std::vector<CuttingPlane> unit = scene(1.0);
  const VoxelSizeChoice c1 = automaticVoxelSize(unit, sectionWidths(unit), {}, 4000000);
  EXPECT_GT(c1.voxel_mm, 0);
  for (const double scale : {1e-3, 0.037, 25.4, 1e3}) {
    SCOPED_TRACE(scale);
    const std::vector<CuttingPlane> planes = scene(scale);
    const VoxelSizeChoice c = automaticVoxelSize(planes, sectionWidths(planes), {}, 4000000);
    EXPECT_NEAR(c.voxel_mm / (scale * c1.voxel_mm), 1.0, 0.06);
    EXPECT_NEAR(double(c.voxels) / double(c1.voxels), 1.0, 0.25);
    EXPECT_EQ(c.limited_by, c1.limited_by);
  }
  // A budget the rule's size exceeds: the size grows until the grid fits.
  const VoxelSizeChoice small = automaticVoxelSize(unit, sectionWidths(unit), {}, 20000);
  EXPECT_EQ(small.limited_by, VoxelSizeLimit::voxel_budget);
  EXPECT_LE(small.voxels, 20000);
  EXPECT_GT(small.voxel_mm, c1.voxel_mm);
  EXPECT_THROW(automaticVoxelSize({}, {}, {}, 4000000), std::invalid_argument);
}

TEST(AutomaticVoxelSize, ThinSectionsGetAFinerGrid) {
  // Thin plates (1 unit thick, 40 across): the median width, not the bounds, decides.
  std::vector<CuttingPlane> planes;
  for (int q = 0; q < 8; ++q) {
    CuttingPlane p;
    p.plane = test::axisPlane(0, 5.0 * q);
    Section s;
    s.outer = {{0, 0}, {40, 0}, {40, 1}, {0, 1}};
    p.sections = {s};
    planes.push_back(p);
  }
  const VoxelSizeChoice c = automaticVoxelSize(planes, sectionWidths(planes), {}, 40000000);
  EXPECT_EQ(c.limited_by, VoxelSizeLimit::section_width);
  EXPECT_NEAR(c.voxel_mm, 0.25, 0.03);  // a quarter of the width, measured within 3 raster steps
}

TEST(AutomaticVoxelSize, TwoSignificantDigitsRoundToNearestOrUp) {
  EXPECT_DOUBLE_EQ(twoSignificantDigits(0.01234), 0.012);
  EXPECT_DOUBLE_EQ(twoSignificantDigits(0.01234, true), 0.013);
  EXPECT_EQ(twoSignificantDigits(0.35, true), 0.35);  // the double nearest 0.35, no rounding noise
  EXPECT_EQ(twoSignificantDigits(0.4123), 0.41);
  EXPECT_EQ(twoSignificantDigits(1.7049), 1.7);
  EXPECT_DOUBLE_EQ(twoSignificantDigits(987.0), 990.0);
}
