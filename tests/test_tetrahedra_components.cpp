// The components of method 3's tetrahedra as the mesh's repairs see them
// (geometry/delaunay/tetrahedra_components.h), under random rigid motions: tetrahedra sharing a
// vertex position are one component; with the boundary's tolerances, a component of a needle
// whose vertices the weld collapses, or of a sliver thinner than the flat thickness, bounds no
// volume and is not counted, while one such tetrahedron joined to a solid one leaves it counted
// once.
#include <gtest/gtest.h>

#include <random>

#include "geometry/delaunay/tetrahedra_components.h"
#include "random_motion.h"

using namespace xsect;

namespace {

/// Adds the tetrahedron on four new vertices (no vertex shared with the others).
void add(TetrahedronSet& t, const std::array<Vec3, 4>& x) {
  const int i = int(t.vertices.size());
  t.vertices.insert(t.vertices.end(), x.begin(), x.end());
  t.corners.push_back({i, i + 1, i + 2, i + 3});
}

}  // namespace

TEST(TetrahedraComponents, CountsTheSolidTheRepairedMeshBounds) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> shift(-50, 50);
  const BoundaryTolerances bounds{0.002, 0.0002};  // a sample spacing of 0.2 mm
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Matrix3d Rm = test::randomRotation(rng);
    const Vec3 o(shift(rng), shift(rng), shift(rng));
    const auto at = [&](double x, double y, double z) { return Vec3(Rm * Vec3(x, y, z) + o); };
    TetrahedronSet t;
    // Two unit tetrahedra sharing the position of one vertex (separate vertices, one position).
    add(t, {at(0, 0, 0), at(1, 0, 0), at(0, 1, 0), at(0, 0, 1)});
    add(t, {at(1, 0, 0), at(2, 0, 0), at(1, 1, 0), at(1, 0, 1)});
    EXPECT_EQ(tetrahedraComponents(t), 1);
    EXPECT_EQ(tetrahedraComponents(t, bounds), 1);
    // A solid tetrahedron 0.001 mm from the first: apart (only equal positions are one).
    add(t, {at(-0.001, 0, 0), at(-1, 0, 0), at(-1, 1, 0), at(-1, 0, 1)});
    EXPECT_EQ(tetrahedraComponents(t), 2);
    EXPECT_EQ(tetrahedraComponents(t, bounds), 2);
    // A needle: three vertices within 0.0013 mm of each other (the weld collapses it), far away.
    add(t, {at(10, 0, 0), at(10.0006, 0.0007, 0), at(10.0006, -0.0006, 0.0001), at(10.02, 0.03, 0.08)});
    // A sliver: four points of one plane up to 1e-6 mm, 1 mm across.
    add(t, {at(20, 0, 0), at(21, 0, 0), at(20, 1, 0), at(20.5, 0.5, 1e-6)});
    EXPECT_EQ(tetrahedraComponents(t), 4);
    EXPECT_EQ(tetrahedraComponents(t, bounds), 2);
    // A sliver on a vertex position of the solid third: its component counts once, as before.
    add(t, {at(-1, 0, 1), at(-2, 0, 1), at(-1, 1, 1), at(-1.5, 0.5, 1 + 1e-6)});
    EXPECT_EQ(tetrahedraComponents(t), 4);
    EXPECT_EQ(tetrahedraComponents(t, bounds), 2);
    // A small solid tetrahedron far away is counted whatever the tolerances.
    add(t, {at(30, 0, 0), at(30.05, 0, 0), at(30, 0.05, 0), at(30, 0, 0.05)});
    EXPECT_EQ(tetrahedraComponents(t), 5);
    EXPECT_EQ(tetrahedraComponents(t, bounds), 3);
  }
}
