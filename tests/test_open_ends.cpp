// Open ends of the data (geometry/scene/open_ends.h) on a sphere of radius 10 mm: a parallel stack
// has its two outermost slices as open ends, on the side away from the others; three orthogonal
// stacks have none (each stack's outermost sections lie within the other stacks'); a section
// beside the stack's end that reaches past it closes that end.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/scene/open_ends.h"

using namespace xsect;

namespace {

/// The plane through `origin` with normal axis `axis` (0, 1, 2), holding the sphere's section (a
/// 64-gon) when the plane cuts it.
CuttingPlane sphereCut(int slice, int axis, double offset, double radius = 10) {
  CuttingPlane p;
  p.slice = slice;
  p.plane.normal = Vec3::Unit(axis);
  p.plane.u = Vec3::Unit((axis + 1) % 3);
  p.plane.v = Vec3::Unit((axis + 2) % 3);
  p.plane.origin = offset * p.plane.normal;
  const double r2 = radius * radius - offset * offset;
  if (r2 > 0) {
    Section s;
    for (int k = 0; k < 64; ++k)
      s.outer.emplace_back(std::sqrt(r2) * std::cos(2 * M_PI * k / 64), std::sqrt(r2) * std::sin(2 * M_PI * k / 64));
    p.sections.push_back(s);
  }
  return p;
}

}  // namespace

TEST(OpenEnds, AStackIsOpenAtBothEndsAndThreeStacksNowhere) {
  std::vector<CuttingPlane> stack;
  for (int i = 0; i < 7; ++i) stack.push_back(sphereCut(i, 2, -6 + 2 * i));
  EXPECT_EQ(openEndSlices(stack, 0.1), (std::vector<int>{0, 6}));
  // Tilted the same way, the stack keeps its ends.
  std::vector<CuttingPlane> tilted = stack;
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.4, Vec3(1, 1, 0).normalized()).toRotationMatrix();
  for (CuttingPlane& p : tilted) {
    p.plane.origin = turn * p.plane.origin;
    p.plane.u = turn * p.plane.u;
    p.plane.v = turn * p.plane.v;
    p.plane.normal = turn * p.plane.normal;
  }
  EXPECT_EQ(openEndSlices(tilted, 0.1), (std::vector<int>{0, 6}));
  // Three orthogonal stacks of 10 planes at the cells' centres (as the phantoms' multi-axial
  // pattern): none.
  std::vector<CuttingPlane> axes;
  for (int axis = 0; axis < 3; ++axis)
    for (int i = 0; i < 10; ++i) axes.push_back(sphereCut(int(axes.size()), axis, -9 + 2 * i));
  EXPECT_TRUE(openEndSlices(axes, 0.1).empty());
  // One upright slice through the stack, reaching past its top end only: the bottom stays open.
  stack.push_back(sphereCut(7, 0, 0));
  for (Vec2& q : stack.back().sections[0].outer) q.y() = std::max(q.y(), -5.0);  // z = v, from -5 mm up
  EXPECT_EQ(openEndSlices(stack, 0.1), (std::vector<int>{0}));
  // Passed by less than the tolerance: still open.
  for (Vec2& q : stack.back().sections[0].outer) q.y() = std::min(q.y(), 6.05);
  EXPECT_EQ(openEndSlices(stack, 0.1), (std::vector<int>{0, 6}));
  // Empty and virtual planes are never open ends.
  std::vector<CuttingPlane> withEmpty = {sphereCut(0, 2, 0), sphereCut(1, 2, 12)};
  EXPECT_EQ(openEndSlices(withEmpty, 0.1), (std::vector<int>{0}));
}
