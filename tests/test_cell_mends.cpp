// What topology control may change next to a plane (geometry/reconstruction/cell_mends.h,
// planesAllow): near a plane, only what the plane's sections say at the projection (either value
// where the contour crosses the voxel); away from planes, anything; next to a plane that saw
// only part of itself, nothing beyond what it saw.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/reconstruction/cell_mends.h"

namespace xsect {
namespace {

CuttingPlane planeWithDisk(double radius) {
  CuttingPlane p;
  p.slice = 0;
  p.plane.origin = Vec3::Zero();
  p.plane.normal = Vec3::UnitZ();
  p.plane.u = Vec3::UnitX();
  p.plane.v = Vec3::UnitY();
  Section s;
  for (int k = 0; k < 128; ++k) {
    const double a = 2 * M_PI * k / 128;
    s.outer.push_back(Vec2(radius * std::cos(a), radius * std::sin(a)));
  }
  p.sections.push_back(s);
  p.observed_everywhere = true;
  return p;
}

TEST(CellMends, PlanesAllowWhatTheirSectionsSayNextToThemAndAnythingAway) {
  const double voxel = 0.5;
  const std::vector<CuttingPlane> planes{planeWithDisk(5)};
  const std::vector<SectionDistanceField> fields{sectionDistanceField(planes[0].sections, 0.05, 4.0)};
  struct Case {
    Vec3 x;
    bool in, out;  ///< allowed to take 1, to take 0
  };
  const std::vector<Case> cases{{Vec3(0, 0, 0.2), true, false},   // inside the disk, next to the plane
                                {Vec3(2, 1, -0.4), true, false},
                                {Vec3(8, 0, 0.2), false, true},   // outside the disk
                                {Vec3(0, -6, -0.3), false, true},
                                {Vec3(5.1, 0, 0.2), true, true},  // the contour crosses the voxel
                                {Vec3(0, 4.85, 0.1), true, true},
                                {Vec3(0, 0, 0.6), true, true},    // beyond one voxel of the plane
                                {Vec3(8, 0, -3), true, true}};
  for (const Case& c : cases) {
    EXPECT_EQ(planesAllow(c.x, true, planes, 1, fields, voxel), c.in) << c.x.transpose();
    EXPECT_EQ(planesAllow(c.x, false, planes, 1, fields, voxel), c.out) << c.x.transpose();
  }
  // The plane is not real (an end plane): it decides nothing.
  EXPECT_TRUE(planesAllow(Vec3(8, 0, 0.2), true, planes, 0, fields, voxel));
  // An image that saw [-6, 6]^2 of its plane: beyond it, nothing changes next to it.
  std::vector<CuttingPlane> seen = planes;
  seen[0].observed_everywhere = false;
  seen[0].extent.min = Vec2(-6, -6);
  seen[0].extent.max = Vec2(6, 6);
  EXPECT_TRUE(planesAllow(Vec3(0, 0, 0.2), true, seen, 1, fields, voxel));
  EXPECT_FALSE(planesAllow(Vec3(8, 0, 0.2), false, seen, 1, fields, voxel));
  EXPECT_FALSE(planesAllow(Vec3(8, 0, 0.2), true, seen, 1, fields, voxel));
}

}  // namespace
}  // namespace xsect
