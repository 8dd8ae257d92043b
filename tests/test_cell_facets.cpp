// The facets of an arrangement cell by clipping a box (cell_facets.h) against CGAL's halfspace
// intersection of every plane (cell_polytope.h): the same facet planes and the same farthest vertex,
// on random arrangements, including points near the box and cells the box closes.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "geometry/arrangement/cell_facets.h"
#include "geometry/sampling/cell_polytope.h"

using namespace xsect;

namespace {

Plane randomPlane(std::mt19937_64& rng, double spread) {
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(-spread, spread);
  Plane p;
  p.normal = Vec3(g(rng), g(rng), g(rng)).normalized();
  p.u = p.normal.unitOrthogonal();
  p.v = p.normal.cross(p.u);
  p.origin = Vec3(u(rng), u(rng), u(rng));
  return p;
}

}  // namespace

TEST(CellFacets, EqualTheFacetsOfTheExactHalfspaceIntersection) {
  std::mt19937_64 rng(3);
  const Vec3 lo = Vec3::Constant(-10), hi = Vec3::Constant(10);
  std::uniform_real_distribution<double> inBox(-9.9, 9.9);
  ClippedBox box;
  int cells = 0, closedByTheBox = 0;
  for (const int count : {1, 4, 12, 40, 120}) {
    for (int trial = 0; trial < 40; ++trial) {
      std::vector<Plane> planes;
      std::vector<Vec3> normals;
      std::vector<double> offsets;
      for (int i = 0; i < count; ++i) {
        planes.push_back(randomPlane(rng, 8.0));
        normals.push_back(planes.back().normal);
        offsets.push_back(planes.back().normal.dot(planes.back().origin));
      }
      const Vec3 x(inBox(rng), inBox(rng), inBox(rng));
      std::vector<std::pair<double, int>> byDistance;
      std::vector<int> sides;
      for (int i = 0; i < count; ++i) {
        const double s = planes[std::size_t(i)].signedDistance(x);
        byDistance.push_back({std::abs(s), i});
        sides.push_back(s >= 0 ? 1 : -1);
      }
      std::sort(byDistance.begin(), byDistance.end());
      if (byDistance.front().first < 1e-3) continue;  // the exact polytope needs a strict interior
      std::vector<int> order;
      std::vector<double> bound;
      for (const auto& [d, i] : byDistance) {
        order.push_back(i);
        bound.push_back(d);
      }
      std::vector<int> facets;
      const double farthest = cellFacets(x, normals, offsets, order, bound, lo, hi, 1e-9, box, &facets);
      const CellPolytope exact = cellPolytope(planes, sides, x, lo, hi);
      ASSERT_FALSE(exact.empty());
      // A plane is a facet of the exact polytope when three of its vertices lie on it, not on a line.
      std::set<int> exactFacets;
      for (int i = 0; i < count; ++i) {
        std::vector<Vec3> on;
        for (const Vec3& v : exact.vertices)
          if (std::abs(planes[std::size_t(i)].signedDistance(v)) < 1e-7) on.push_back(v);
        for (std::size_t a = 2; a < on.size(); ++a)
          if ((on[1] - on[0]).cross(on[a] - on[0]).norm() > 1e-8) {
            exactFacets.insert(i);
            break;
          }
      }
      EXPECT_EQ(std::set<int>(facets.begin(), facets.end()), exactFacets) << count << " planes, trial " << trial;
      double far = 0;
      bool touchesBox = false;
      for (const Vec3& v : exact.vertices) {
        far = std::max(far, (v - x).norm());
        touchesBox = touchesBox || (v - lo).cwiseAbs().minCoeff() < 1e-9 || (hi - v).cwiseAbs().minCoeff() < 1e-9;
      }
      EXPECT_NEAR(farthest, far, 1e-7 * (1 + far));
      ++cells;
      closedByTheBox += touchesBox;
    }
  }
  EXPECT_GT(cells, 180);
  EXPECT_GT(closedByTheBox, 20);      // cells the box closes
  EXPECT_LT(closedByTheBox, cells);   // and cells the planes close alone
}

TEST(CellFacets, StopsAtTheCellNotAtTheNumberOfPlanes) {
  // A unit cube of six planes around x, then many parallel planes farther out: none is a facet,
  // and the clipping stops before them (their bound exceeds the cube's farthest vertex). The box
  // is fresh, so the count of half-spaces offered is this call's.
  std::vector<Vec3> normals;
  std::vector<double> offsets;
  for (int k = 0; k < 3; ++k)
    for (const double side : {-0.5, 0.5}) {
      normals.push_back(Vec3::Unit(k));
      offsets.push_back(side);
    }
  for (int i = 0; i < 200; ++i) {
    normals.push_back(Vec3::UnitX());
    offsets.push_back(2.0 + 0.01 * i);
  }
  std::vector<int> order;
  std::vector<double> bound;
  for (std::size_t q = 0; q < normals.size(); ++q) {
    order.push_back(int(q));
    bound.push_back(std::abs(offsets[q]));
  }
  ClippedBox box;
  std::vector<int> facets;
  const double farthest = cellFacets(Vec3::Zero(), normals, offsets, order, bound, Vec3::Constant(-100),
                                     Vec3::Constant(100), 1e-9, box, &facets);
  EXPECT_EQ(facets, (std::vector<int>{0, 1, 2, 3, 4, 5}));
  EXPECT_NEAR(farthest, std::sqrt(0.75), 1e-12);
  // The six faces, and not one of the 200 planes beyond the cube's farthest vertex, were offered.
  EXPECT_EQ(box.clipsOffered(), 6);
}
