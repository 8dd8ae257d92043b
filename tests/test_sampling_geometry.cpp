// The pieces of the sampling diagnosis (issue 18) against what they must be: the lattice scan's
// bounds against the exact heights of cells (thesis Def. 23), tangent discs against circles and
// annuli with and without contour noise, the surface normals and angles α measured at contour
// crossings against a sphere's (Def. 26), and the reach bounds from the sections alone against the
// true reach of a sphere and a torus cut by parallel and random planes (they must never fall below);
// method 2's cell height h'_C (Def. 31) bounded from above on a cube and on random cells against
// brute force.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/arrangement/section_arrangement.h"
#include "geometry/core/plane_of_pose.h"
#include "geometry/evaluation/medial_axis_samples.h"
#include "geometry/sampling/cell_height.h"
#include "geometry/sampling/cell_scan.h"
#include "geometry/sampling/contour_crossings.h"
#include "geometry/sampling/neighbour_angles.h"
#include "geometry/sampling/reach_bound.h"
#include "geometry/sampling/section_cell_height.h"
#include "geometry/sampling/tangent_disc.h"
#include "geometry/scene/section_scene.h"
#include "section_fixtures.h"

using namespace xsect;

namespace {

using test::circle;

/// A counter-clockwise circle whose vertices are moved radially by up to ±noise.
Ring noisyCircle(const Vec2& c, double r, int n, double noise, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-noise, noise);
  Ring ring = circle(c, r, n);
  for (Vec2& q : ring) q = c + (q - c) * ((r + u(rng)) / r);
  return ring;
}

/// A plane with the sections a sphere (centre c, radius R) leaves on it.
CuttingPlane sphereCut(const Plane& P, const Vec3& c, double R, int slice) {
  CuttingPlane cp;
  cp.slice = slice;
  cp.plane = P;
  cp.observed_everywhere = true;
  const double d = P.signedDistance(c);
  if (std::abs(d) < R) cp.sections.push_back(Section{circle(P.toPlane(c), std::sqrt(R * R - d * d), 360), {}, 1});
  return cp;
}

/// `count` random planes within `spread` of the sphere's centre, with its sections.
std::vector<CuttingPlane> randomSphereCuts(unsigned seed, int count, const Vec3& c, double R, double spread) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(-spread, spread);
  std::vector<CuttingPlane> planes;
  for (int k = 0; k < count; ++k) {
    const Vec3 n = Vec3(g(rng), g(rng), g(rng)).normalized();
    planes.push_back(sphereCut(planeThrough(c + u(rng) * n, n), c, R, k));
  }
  return planes;
}

/// z = const planes through a torus about the z axis (major R, minor r): annuli.
CuttingPlane torusCut(double z, double R, double r, int slice) {
  CuttingPlane cp;
  cp.slice = slice;
  cp.plane = planeThrough(Vec3(0, 0, z), Vec3::UnitZ());
  cp.observed_everywhere = true;
  if (std::abs(z) < r) {
    const double w = std::sqrt(r * r - z * z);
    const Vec2 c = cp.plane.toPlane(Vec3::Zero());
    cp.sections.push_back(Section{circle(c, R + w, 720), {circle(c, R - w, 720, false)}, 1});
  }
  return cp;
}

}  // namespace

// Every scanned cell's exact height lies between the scan's bounds, over five random arrangements.
TEST(SamplingGeometry, LatticeScanBoundsTheExactHeights) {
  const Vec3 lo(-10, -10, -10), hi(10, 10, 10);
  int nontrivial = 0;
  for (int seed = 0; seed < 5; ++seed) {
    std::mt19937 rng(seed);
    std::vector<Plane> planes = test::randomPlanes(rng, 12, 8);
    for (const Plane& face : test::boxFaces(lo, hi)) planes.push_back(face);
    const CellKeys keys(planes);
    const CellScan scan = scanCells(planes, keys, lo, hi, 0.8);
    ASSERT_GT(scan.cells.size(), 20u);
    for (std::size_t i = 0; i < scan.cells.size(); i += 3) {
      const ScannedCell& c = scan.cells[i];
      const CellHeight h = cellHeight(planes, keys.sides(c.farthest), lo - Vec3::Constant(1), hi + Vec3::Constant(1), false);
      EXPECT_LE(c.max_distance_mm, h.height + 1e-5) << "seed " << seed << " cell " << i;
      EXPECT_GE(scan.heightBound(c), h.height - 1e-9) << "seed " << seed << " cell " << i;
      nontrivial += h.height > scan.half_diagonal_mm;
      EXPECT_EQ(keys.of(h.centre), c.key) << "the ball's centre lies in the cell";
    }
  }
  EXPECT_GT(nontrivial, 20);
}

TEST(SamplingGeometry, TangentDiscsOfCirclesAndAnnuli) {
  const std::vector<Section> disc{Section{circle(Vec2(0, 0), 5, 720), {}, 1}};
  EXPECT_NEAR(tangentDiscRadius(disc, Vec2(5, 0), Vec2(-1, 0), 0), 5, 0.01);
  EXPECT_TRUE(std::isinf(tangentDiscRadius(disc, Vec2(5, 0), Vec2(1, 0), 0)));
  const std::vector<Section> annulus{Section{circle(Vec2(0, 0), 5, 720), {circle(Vec2(0, 0), 2, 720, false)}, 1}};
  EXPECT_NEAR(tangentDiscRadius(annulus, Vec2(5, 0), Vec2(-1, 0), 0), 1.5, 0.01);
  EXPECT_NEAR(tangentDiscRadius(annulus, Vec2(2, 0), Vec2(-1, 0), 0), 2, 0.01) << "outside, in the hole";
  // Vertices off the circle by at most σ/2 never cut the true disc short.
  for (int seed = 0; seed < 20; ++seed) {
    std::mt19937 rng(seed);
    const double sigma = 0.1;
    const std::vector<Section> noisy{Section{noisyCircle(Vec2(0, 0), 5, 720, sigma / 2, rng), {}, 1}};
    const double t = 2 * M_PI * seed / 20;
    const Vec2 a = 5 * Vec2(std::cos(t), std::sin(t));
    const double w = tangentDiscRadius(noisy, a, -a.normalized(), sigma);
    EXPECT_GE(w, 5.0 - 1e-9) << "seed " << seed;
    EXPECT_LT(w, 7.0) << "seed " << seed;
  }
}

// At the crossings of 24 random planes' contours on a sphere: the point on the sphere, the normal
// the sphere's, α as defined (angle of the plane with the normal) and interior bounds above R.
TEST(SamplingGeometry, ContourCrossingsMeasureTheSphere) {
  const Vec3 c(1, 2, 3);
  const double R = 8;
  const std::vector<CuttingPlane> planes = randomSphereCuts(4, 24, c, R, 6);
  const SectionArrangement arrangement = arrangeSections(planes, 0.5);
  const std::vector<ContourCrossing> xs = contourCrossings(planes, arrangement, 0.05);
  ASSERT_GT(xs.size(), 50u);
  for (const ContourCrossing& x : xs) {
    EXPECT_NEAR((x.point - c).norm(), R, 0.01);
    const Vec3 n = (x.point - c).normalized();
    EXPECT_GT(x.normal.dot(n), std::cos(3 * M_PI / 180)) << "outward normal";
    const double alpha = std::asin(std::min(1.0, std::abs(n.dot(planes[std::size_t(x.plane_a)].plane.normal)))) * 180 / M_PI;
    EXPECT_NEAR(x.alpha_a_deg, alpha, 3);
    EXPECT_GE(x.interior_bound_mm, R);
    EXPECT_TRUE(std::isinf(x.exterior_bound_mm)) << "a ball outside a sphere is not bounded";
  }
}

// Reach bounds from the sections alone never fall below the true reach, and the planes around the
// ends of a stack do bound it: a sphere (reach_i = R) in a parallel stack and random planes, a torus
// (reach_i = r, reach_e = R - r) in a parallel stack.
TEST(SamplingGeometry, ReachBoundsFromTheSectionsAreBounds) {
  const auto check = [](const std::vector<CuttingPlane>& real, double reachI, double reachE, const char* what) {
    ReconstructionParams params;
    params.voxel_mm = 0.25;
    const SectionScene scene = sectionScene(real, params);
    const SectionArrangement arrangement = arrangeSections(scene.planes, 0.5);
    const std::vector<ContourReachBound> bounds =
        contourReachBounds(scene.planes, scene.fields, arrangement, 0.1, 100.0);
    ASSERT_GT(bounds.size(), 100u) << what;
    int finite = 0;
    for (const ContourReachBound& b : bounds) {
      EXPECT_GE(b.interior_mm, reachI) << what;
      EXPECT_GE(b.exterior_mm, reachE) << what;
      finite += std::isfinite(b.interior_mm) || std::isfinite(b.exterior_mm);
    }
    EXPECT_GT(finite, 0) << what << ": no contour point bounded";
  };
  const Vec3 c(0.5, -0.5, 0.25);
  std::vector<CuttingPlane> stack;
  for (int k = -5; k <= 5; ++k) stack.push_back(sphereCut(planeThrough(c + Vec3(0, 0, 1.5 * k), Vec3::UnitZ()), c, 8, k + 5));
  check(stack, 8, INFINITY, "sphere, parallel stack");
  check(randomSphereCuts(9, 16, c, 8, 7), 8, INFINITY, "sphere, random planes");
  std::vector<CuttingPlane> torus;
  for (int k = -3; k <= 3; ++k) torus.push_back(torusCut(1.25 * k + 0.1, 12, 4, k + 3));
  check(torus, 4, 8, "torus, parallel stack");
}

// The medial axis of a torus about z (major R, minor r): inside, the core circle; outside, the z
// axis. Every sample lies within two lattice steps of them, and both are found.
TEST(SamplingGeometry, MedialAxisSamplesOfATorus) {
  const double R = 12, r = 4;
  const auto sdf = [&](const Vec3& x) {
    const double q = std::hypot(x.x(), x.y()) - R;
    return std::hypot(q, x.z()) - r;
  };
  const double h = 0.5;
  const MedialAxisSamples m = medialAxisSamples(sdf, Vec3(-18, -18, -6), Vec3(18, 18, 6), h, 0.9, 2 * h);
  ASSERT_GT(m.interior.size(), 50u);
  ASSERT_GT(m.exterior.size(), 5u);
  for (const Vec3& x : m.interior) EXPECT_LT(std::hypot(std::hypot(x.x(), x.y()) - R, x.z()), 2 * h) << x.transpose();
  for (const Vec3& x : m.exterior) EXPECT_LT(std::hypot(x.x(), x.y()), 2 * h) << x.transpose();
}

// α estimated between near-parallel slices of a sphere (R = 8, slices 0.5 mm apart) follows the
// true angle asin(|z| / R) where the sphere is not nearly tangent to the slices.
TEST(SamplingGeometry, NeighbourAnglesFollowTheSphere) {
  const Vec3 c(0.3, -0.2, 0.1);
  const double R = 8;
  std::vector<CuttingPlane> stack;
  for (int k = -14; k <= 14; ++k) stack.push_back(sphereCut(planeThrough(c + Vec3(0, 0, 0.5 * k), Vec3::UnitZ()), c, R, k + 14));
  const SectionArrangement arrangement = arrangeSections(stack, 0.5);
  const std::vector<NeighbourAngle> est = neighbourAngles(stack, arrangement, 0.05);
  int checked = 0;
  for (const NeighbourAngle& e : est) {
    const SectionPoint& s = arrangement.points[std::size_t(e.point)];
    const double z = stack[std::size_t(s.plane)].plane.signedDistance(c);
    if (std::abs(z) > 6) continue;
    EXPECT_NEAR(e.alpha_deg, std::asin(std::abs(z) / R) * 180 / M_PI, 5) << "z " << z;
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

// A point on two planes (where a contour crosses a trace) keyed with both sides forced is the
// point moved a little into that quadrant; the clearance leaves both planes out.
TEST(SamplingGeometry, CellKeysForceTheSidesOfTwoPlanes) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  std::vector<Plane> planes;
  for (int k = 0; k < 9; ++k) planes.push_back(planeThrough(Vec3(g(rng), g(rng), g(rng)), Vec3(g(rng), g(rng), g(rng))));
  const CellKeys keys(planes);
  for (int a = 0; a < 9; ++a)
    for (int b = 0; b < 9; ++b) {
      if (a == b) continue;
      // A point on both planes: on their common line, near the origin.
      const Vec3 d = planes[a].normal.cross(planes[b].normal).normalized();
      Eigen::Matrix3d m;
      m << planes[a].normal.transpose(), planes[b].normal.transpose(), d.transpose();
      const Vec3 x = m.colPivHouseholderQr().solve(
          Vec3(planes[a].normal.dot(planes[a].origin), planes[b].normal.dot(planes[b].origin), 0));
      for (const int sa : {-1, 1})
        for (const int sb : {-1, 1}) {
          const Vec3 moved = x + 1e-7 * (sa * planes[a].normal + sb * planes[b].normal);
          double clearance = 0;
          EXPECT_EQ(keys.of(x, a, sa, &clearance, b, sb), keys.of(moved)) << a << " " << b;
          EXPECT_EQ(keys.sides(x, a, sa, b, sb), keys.sides(moved)) << a << " " << b;
          EXPECT_GT(clearance, 1e-6) << "planes a and b are not counted";
        }
    }
}

TEST(SamplingGeometry, SectionHeightBoundsMethod2sHeight) {
  // The unit cube, its faces' normals outward: the cell lies on their negative sides.
  std::vector<Plane> cube;
  for (int a = 0; a < 3; ++a) {
    cube.push_back(planeThrough(Vec3::Zero(), -Vec3::Unit(a)));
    cube.push_back(planeThrough(Vec3::Ones(), Vec3::Unit(a)));
  }
  const std::vector<int> inside(6, -1);
  const Vec3 lo = -Vec3::Ones(), hi = 2 * Vec3::Ones(), mid = Vec3::Constant(0.5);
  const auto face = [](double z) {
    std::vector<Vec3> pts;
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; j <= 20; ++j) pts.emplace_back(i / 20.0, j / 20.0, z);
    return pts;
  };
  const double tol = 0.05 * std::sqrt(0.5) + 0.06;  // the points' gaps and the relative resolution
  // A section covering the bottom face: h' = 1 (the top face).
  SectionHeightBound b = sectionHeightBound(cube, inside, mid, lo, hi, face(0), 0, 0.01);
  EXPECT_GE(b.upper_mm, 1 - 1e-9);
  EXPECT_LE(b.upper_mm, 1 + tol);
  EXPECT_NEAR(b.farthest.z(), 1, 0.1);
  // Bottom and top: h' = 1/2.
  std::vector<Vec3> both = face(0), top = face(1);
  both.insert(both.end(), top.begin(), top.end());
  b = sectionHeightBound(cube, inside, mid, lo, hi, both, 0, 0.01);
  EXPECT_GE(b.upper_mm, 0.5 - 1e-9);
  EXPECT_LE(b.upper_mm, 0.5 + tol);
  // A section reduced to a corner: h' = √3; a target above it stops early, still a bound.
  b = sectionHeightBound(cube, inside, mid, lo, hi, {Vec3::Zero()}, 0, 0.01);
  EXPECT_GE(b.upper_mm, std::sqrt(3.0) - 1e-9);
  EXPECT_LE(b.upper_mm, std::sqrt(3.0) * 1.06);
  b = sectionHeightBound(cube, inside, mid, lo, hi, {Vec3::Zero()}, 3, 0.01);
  EXPECT_GE(b.upper_mm, std::sqrt(3.0) - 1e-9);
  EXPECT_LT(b.upper_mm, 3);
  EXPECT_TRUE(std::isinf(sectionHeightBound(cube, inside, Vec3(2, 0.5, 0.5), lo, hi, {Vec3::Zero()}, 0, 0.01).upper_mm))
      << "an interior point outside the cell is refused";

  // Random cells of random planes, random points: never below the brute-force maximum, and close.
  int checked = 0;
  double excess = 0;
  for (int seed = 0; seed < 4; ++seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(-8, 8), w(-10, 10);
    const Vec3 blo(-10, -10, -10), bhi(10, 10, 10);
    std::vector<Plane> planes;
    for (int k = 0; k < 10; ++k) planes.push_back(planeThrough(Vec3(u(rng), u(rng), u(rng)), Vec3(g(rng), g(rng), g(rng))));
    const CellKeys keys(planes);
    const CellScan scan = scanCells(planes, keys, blo, bhi, 1.0);
    std::vector<Vec3> samples;
    for (int k = 0; k < 200000; ++k) samples.emplace_back(w(rng), w(rng), w(rng));
    for (std::size_t i = 0; i < scan.cells.size(); i += 5) {
      const ScannedCell& c = scan.cells[i];
      if (c.max_distance_mm <= 0) continue;
      std::vector<Vec3> pts;
      for (int k = 0; k < 12; ++k) pts.emplace_back(u(rng), u(rng), u(rng));
      double brute = 0;
      for (const Vec3& x : samples) {
        if (keys.of(x) != c.key) continue;
        double d = 1e300;
        for (const Vec3& p : pts) d = std::min(d, (x - p).norm());
        brute = std::max(brute, d);
      }
      const SectionHeightBound sb = sectionHeightBound(planes, keys.sides(c.farthest), c.farthest, blo - Vec3::Constant(1e-3), bhi + Vec3::Constant(1e-3), pts, 0, 0.05);
      EXPECT_GE(sb.upper_mm, brute - 1e-9) << "seed " << seed << " cell " << i;
      excess += sb.upper_mm / brute;
      ++checked;
    }
  }
  EXPECT_GT(checked, 30);
  // Close on average (random samples miss the cells' corners, so the brute force is low too).
  EXPECT_LT(excess / checked, 1.1);
}
