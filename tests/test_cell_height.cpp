// h_C (thesis ch. 1 §2.3, Def. 23): the largest ball inside a cell of the arrangement, against
// closed forms (slabs, boxes, the inradius of random tetrahedra) and, in random arrangements, the
// definition itself: the ball lies in the cell and no point of the cell is farther from its
// boundary.
#include <gtest/gtest.h>

#include <random>

#include "geometry/sampling/cell_height.h"

using namespace xsect;

namespace {

Plane planeOf(const Vec3& normal, const Vec3& origin) {
  Plane p;
  p.normal = normal.normalized();
  p.origin = origin;
  const Vec3 a = std::abs(p.normal.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  p.u = p.normal.cross(a).normalized();
  p.v = p.normal.cross(p.u);
  return p;
}

std::vector<int> sidesOf(const std::vector<Plane>& planes, const Vec3& x) {
  std::vector<int> s;
  for (const Plane& p : planes) s.push_back(p.signedDistance(x) > 0 ? 1 : -1);
  return s;
}

}  // namespace

TEST(CellHeight, ParallelPlanesGiveHalfTheirSpacing) {
  const std::vector<Plane> planes{planeOf(Vec3::UnitZ(), Vec3(0, 0, 0)), planeOf(Vec3::UnitZ(), Vec3(0, 0, 1)),
                                  planeOf(Vec3::UnitZ(), Vec3(0, 0, 3))};
  const CellHeight h = cellHeight(planes, sidesOf(planes, Vec3(0, 0, 2)), Vec3(-10, -10, -10), Vec3(10, 10, 10));
  EXPECT_NEAR(h.height, 1.0, 1e-12);
  EXPECT_NEAR(h.centre.z(), 2.0, 1e-12);
  EXPECT_FALSE(h.open);
  EXPECT_EQ(h.bounding_planes, (std::vector<int>{1, 2}));
  // Beyond the last plane: closed only by the box (z from 3 to 10): open, half of 7.
  const CellHeight beyond = cellHeight(planes, sidesOf(planes, Vec3(0, 0, 5)), Vec3(-10, -10, -10), Vec3(10, 10, 10));
  EXPECT_NEAR(beyond.height, 3.5, 1e-12);
  EXPECT_TRUE(beyond.open);
}

TEST(CellHeight, RandomTetrahedraGiveTheirInradius) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-5, 5);
  int tested = 0;
  for (int k = 0; k < 50; ++k) {
    Vec3 v[4];
    for (auto& x : v) x = Vec3(u(rng), u(rng), u(rng));
    const double volume = std::abs((v[1] - v[0]).dot((v[2] - v[0]).cross(v[3] - v[0]))) / 6;
    if (volume < 1) continue;  // flat ones: the closed form loses digits
    std::vector<Plane> planes;
    double area = 0;
    Vec3 incentre = Vec3::Zero();
    for (int f = 0; f < 4; ++f) {
      const Vec3 &a = v[(f + 1) % 4], &b = v[(f + 2) % 4], &c = v[(f + 3) % 4];
      const Vec3 n = (b - a).cross(c - a);
      planes.push_back(planeOf(n, a));
      area += 0.5 * n.norm();
      incentre += 0.5 * n.norm() * v[f];  // the incentre weights each vertex by its opposite face
    }
    incentre /= area;
    const Vec3 centroid = (v[0] + v[1] + v[2] + v[3]) / 4;
    const CellHeight h = cellHeight(planes, sidesOf(planes, centroid), Vec3::Constant(-20), Vec3::Constant(20));
    EXPECT_NEAR(h.height, 3 * volume / area, 1e-9 * (1 + 3 * volume / area)) << k;
    EXPECT_LT((h.centre - incentre).norm(), 1e-7) << k;
    EXPECT_FALSE(h.open);
    EXPECT_EQ(h.bounding_planes.size(), 4u);
    ++tested;
  }
  EXPECT_GT(tested, 30);
}

// Random arrangements of 25 planes: for cells met by random points, the ball is inside the cell
// (and the box) and no sampled point of the cell is farther than h_C from its boundary (the
// distance from a point of a convex cell to its boundary is its least slack over the planes).
TEST(CellHeight, BallIsInsideAndNoPointIsDeeperInRandomArrangements) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(-4, 4);
  const Vec3 lo = Vec3::Constant(-4), hi = Vec3::Constant(4);
  int cells = 0;
  for (int trial = 0; trial < 8; ++trial) {
    std::vector<Plane> planes;
    for (int j = 0; j < 25; ++j) planes.push_back(planeOf(Vec3(g(rng), g(rng), g(rng)), Vec3(u(rng), u(rng), u(rng))));
    const auto depth = [&](const Vec3& x) {
      double d = std::min((x - lo).minCoeff(), (hi - x).minCoeff());
      for (const Plane& p : planes) d = std::min(d, std::abs(p.signedDistance(x)));
      return d;
    };
    for (int c = 0; c < 10; ++c) {
      const Vec3 seed(u(rng), u(rng), u(rng));
      const std::vector<int> sides = sidesOf(planes, seed);
      const CellHeight h = cellHeight(planes, sides, lo, hi);
      ASSERT_GT(h.height, 0) << "the seed's cell has an interior";
      EXPECT_GE(depth(h.centre), h.height - 1e-9) << "the ball lies in the cell";
      EXPECT_EQ(sidesOf(planes, h.centre), sides) << "the centre lies in the seed's cell";
      EXPECT_LE(depth(seed), h.height + 1e-9);
      for (int s = 0; s < 300; ++s) {
        const Vec3 x(u(rng), u(rng), u(rng));
        if (sidesOf(planes, x) == sides) EXPECT_LE(depth(x), h.height + 1e-9);
      }
      ++cells;
    }
  }
  EXPECT_EQ(cells, 80);
}

// `open` says whether the box limits the height, wherever the solver puts a ball that may slide:
// a slab in a box off the origin is closed by its planes; a cell the box cuts is open; a cell that
// does not meet the box is open with height 0.
TEST(CellHeight, OpenMeansTheBoxLimitsTheHeight) {
  const std::vector<Plane> slab{planeOf(Vec3::UnitZ(), Vec3(0, 0, 5)), planeOf(Vec3::UnitZ(), Vec3(0, 0, 6))};
  const std::vector<int> between{1, -1};
  const CellHeight h = cellHeight(slab, between, Vec3(0, 0, 0), Vec3(20, 20, 20));
  EXPECT_NEAR(h.height, 0.5, 1e-12);
  EXPECT_FALSE(h.open) << "centre " << h.centre.transpose();
  // The box cuts the slab to 0.6 mm: open, height 0.3.
  const CellHeight cut = cellHeight(slab, between, Vec3(0, 0, 0), Vec3(20, 20, 5.6));
  EXPECT_NEAR(cut.height, 0.3, 1e-12);
  EXPECT_TRUE(cut.open);
  // The slab lies beyond the box.
  const CellHeight missed = cellHeight(slab, between, Vec3(0, 0, 0), Vec3(20, 20, 4));
  EXPECT_EQ(missed.height, 0.0);
  EXPECT_TRUE(missed.open);
}

TEST(CellHeight, RefusesMismatchedInput) {
  const std::vector<Plane> planes{planeOf(Vec3::UnitZ(), Vec3::Zero())};
  EXPECT_THROW(cellHeight(planes, {}, Vec3::Constant(-1), Vec3::Constant(1)), std::invalid_argument);
  EXPECT_THROW(cellHeight(planes, {1}, Vec3::Constant(1), Vec3::Constant(-1)), std::invalid_argument);
  std::vector<Plane> scaled = planes;
  scaled[0].normal *= 2;
  EXPECT_THROW(cellHeight(scaled, {1}, Vec3::Constant(-1), Vec3::Constant(1)), std::invalid_argument);
}
