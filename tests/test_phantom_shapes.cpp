// Phantom shapes and slicing patterns (geometry/phantom_shape.h, geometry/slicing_pattern.h):
// exactness of the signed distances, known values, bounds, validation, the vessel tree's
// clearance, the Fig. 1.11 pair's shared sections, and the geometry of every slicing pattern.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "geometry/ellipsoid_distance.h"
#include "geometry/phantom_shape.h"
#include "geometry/plane_of_pose.h"
#include "geometry/slicing_pattern.h"
#include "geometry/vessel_tree.h"

using namespace xsect;

namespace {

PhantomShape make(const std::string& kind, std::map<std::string, double> params,
                  const Vec3& centre = Vec3::Zero(), const Vec3& euler = Vec3::Zero()) {
  PhantomShape s;
  s.kind = kind;
  s.params = std::move(params);
  s.centre = centre;
  s.rotation = rotationFromEulerXyzDeg(euler);
  EXPECT_FALSE(checkPhantomShape(s).has_value()) << kind;
  return completePhantomShape(s);
}

std::vector<PhantomShape> exactShapes() {
  const Vec3 c(3, -2, 5), e(20, 35, -10);
  return {make("sphere", {{"radius", 7}}, c, e),
          make("ellipsoid", {{"a", 9}, {"b", 6}, {"c", 4}}, c, e),
          make("torus", {{"major_radius", 10}, {"minor_radius", 3}}, c, e),
          make("genus2", {{"disk_radius", 20}, {"hole_radius", 5}, {"hole_offset", 8},
                          {"offset_radius", 2.5}}, c, e),
          make("hollow_sphere", {{"outer_radius", 10}, {"inner_radius", 6}}, c, e),
          make("two_spheres", {{"radius", 5}, {"separation", 14}}, c, e)};
}

std::vector<PhantomShape> allShapes() {
  auto v = exactShapes();
  const Vec3 c(1, 2, 3), e(10, -20, 30);
  v.push_back(make("vessel_tree", {{"length", 10}, {"radius", 1}, {"levels", 3}}, c, e));
  v.push_back(make("twisted_cylinder", {{"inner_radius", 6}, {"outer_radius", 10},
                                        {"height", 20}}, c, e));
  v.push_back(make("notched_torus", {{"inner_radius", 6}, {"outer_radius", 10},
                                     {"height", 20}}, c, e));
  return v;
}

Vec3 gradient(const PhantomShape& s, const Vec3& x, double h = 1e-6) {
  Vec3 g;
  for (int k = 0; k < 3; ++k) {
    const Vec3 d = h * Vec3::Unit(k);
    g[k] = (signedDistance(s, x + d) - signedDistance(s, x - d)) / (2 * h);
  }
  return g;
}

Vec3 randomIn(std::mt19937_64& rng, const Vec3& lo, const Vec3& hi) {
  std::uniform_real_distribution<double> u(0, 1);
  return lo + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(hi - lo);
}

}  // namespace

TEST(PhantomShapes, ExactDistanceHasUnitGradientAndProjectsOntoSurface) {
  std::mt19937_64 rng(11);
  for (const auto& s : exactShapes()) {
    ASSERT_TRUE(hasExactDistance(s)) << s.kind;
    Vec3 lo, hi;
    bounds(s, &lo, &hi);
    lo -= Vec3::Constant(3);
    hi += Vec3::Constant(3);
    const double r = reach(s);
    ASSERT_GT(r, 0) << s.kind;
    int tested = 0;
    for (int k = 0; k < 20000 && tested < 300; ++k) {
      const Vec3 x = randomIn(rng, lo, hi);
      const double d = signedDistance(s, x);
      if (std::abs(d) > 0.9 * r) continue;  // inside the reach: no medial axis nearby
      ++tested;
      const Vec3 g = gradient(s, x);
      EXPECT_NEAR(g.norm(), 1.0, 1e-4) << s.kind << " at " << x.transpose();
      const Vec3 foot = x - d * g.normalized();
      EXPECT_NEAR(signedDistance(s, foot), 0.0, 1e-5) << s.kind << " at " << x.transpose();
    }
    EXPECT_GE(tested, 300) << s.kind;
  }
}

TEST(PhantomShapes, KnownValues) {
  const Vec3 c(3, -2, 5);
  const Eigen::Matrix3d R = rotationFromEulerXyzDeg(Vec3(20, 35, -10));
  const auto s = exactShapes();  // same order and placement as above
  auto at = [&](int i, const Vec3& local) { return signedDistance(s[i], c + R * local); };
  EXPECT_NEAR(at(0, Vec3::Zero()), -7, 1e-12);
  EXPECT_NEAR(at(0, Vec3(0, 0, 10)), 3, 1e-12);
  EXPECT_NEAR(at(1, Vec3::Zero()), -4, 1e-9);          // nearest: end of the shortest axis
  EXPECT_NEAR(at(1, Vec3(12, 0, 0)), 3, 1e-9);         // beyond the end of the longest axis
  EXPECT_NEAR(at(1, Vec3(0, 0, 7)), 3, 1e-9);
  EXPECT_NEAR(at(2, Vec3(10, 0, 0)), -3, 1e-12);       // on the core circle
  EXPECT_NEAR(at(2, Vec3::Zero()), 7, 1e-12);          // the hole's centre
  EXPECT_NEAR(at(3, Vec3(8, 0, 0)), 2.5, 1e-12);       // hole centre: 5 - 2.5
  EXPECT_NEAR(at(3, Vec3::Zero()), -2.5, 1e-12);       // on the bridge between the holes
  EXPECT_NEAR(at(3, Vec3(0, 0, 4)), 1.5, 1e-12);
  EXPECT_NEAR(at(3, Vec3(24, 0, 0)), 1.5, 1e-12);      // beyond the rim
  EXPECT_NEAR(at(4, Vec3::Zero()), 6, 1e-12);          // the cavity's centre is outside
  EXPECT_NEAR(at(4, Vec3(8, 0, 0)), -2, 1e-12);
  EXPECT_NEAR(at(5, Vec3::Zero()), 2, 1e-12);          // between the spheres
  EXPECT_NEAR(at(5, Vec3(7, 0, 0)), -5, 1e-12);

  EXPECT_EQ(bettiNumbers(s[0]), (Betti{1, 0, 0}));
  EXPECT_EQ(bettiNumbers(s[2]), (Betti{1, 1, 0}));
  EXPECT_EQ(bettiNumbers(s[3]), (Betti{1, 2, 0}));
  EXPECT_EQ(bettiNumbers(s[4]), (Betti{1, 0, 1}));
  EXPECT_EQ(bettiNumbers(s[5]), (Betti{2, 0, 0}));
  EXPECT_DOUBLE_EQ(reach(s[1]), 16.0 / 9.0);
  EXPECT_DOUBLE_EQ(reach(s[2]), 3);
  EXPECT_DOUBLE_EQ(reach(s[3]), 2.5);
  EXPECT_DOUBLE_EQ(reach(s[4]), 2);
  EXPECT_DOUBLE_EQ(reach(s[5]), 2);
}

TEST(PhantomShapes, EllipsoidMatchesBruteForceClosestPoint) {
  const Vec3 axes(9, 6, 4);
  // Dense surface sampling: 600 x 1200 points (spacing < 0.05 mm).
  std::vector<Vec3> surface;
  for (int i = 0; i <= 600; ++i) {
    const double th = M_PI * i / 600;
    for (int j = 0; j < 1200; ++j) {
      const double ph = 2 * M_PI * j / 1200;
      surface.emplace_back(axes.x() * std::sin(th) * std::cos(ph),
                           axes.y() * std::sin(th) * std::sin(ph), axes.z() * std::cos(th));
    }
  }
  std::mt19937_64 rng(5);
  std::vector<Vec3> queries{Vec3::Zero(), Vec3(3, 0, 0), Vec3(0, 2, 0), Vec3(5, 3, 0),
                            Vec3(0, 0, 3.9), Vec3(12, 0, 0.5), Vec3(-2, 1, 0)};
  for (int k = 0; k < 60; ++k) queries.push_back(randomIn(rng, -1.5 * axes, 1.5 * axes));
  for (const Vec3& q : queries) {
    Vec3 foot;
    const double d = ellipsoidSignedDistance(axes, q, &foot);
    double brute = INFINITY;
    for (const Vec3& p : surface) brute = std::min(brute, (p - q).norm());
    EXPECT_LE(std::abs(d), brute + 1e-9) << q.transpose();
    EXPECT_NEAR(std::abs(d), brute, 2e-3) << q.transpose();
    EXPECT_NEAR(foot.cwiseQuotient(axes).squaredNorm(), 1.0, 1e-9) << q.transpose();
    EXPECT_NEAR((foot - q).norm(), std::abs(d), 1e-9);
    EXPECT_EQ(d < 0, q.cwiseQuotient(axes).squaredNorm() < 1) << q.transpose();
  }
}

TEST(PhantomShapes, BoundsContainEveryInsidePoint) {
  std::mt19937_64 rng(3);
  for (const auto& s : allShapes()) {
    Vec3 lo, hi;
    bounds(s, &lo, &hi);
    const Vec3 pad = 0.5 * (hi - lo);
    int inside = 0;
    for (int k = 0; k < 20000; ++k) {
      const Vec3 x = randomIn(rng, lo - pad, hi + pad);
      if (signedDistance(s, x) < 0) {
        ++inside;
        EXPECT_TRUE((x.array() >= lo.array()).all() && (x.array() <= hi.array()).all())
            << s.kind << " " << x.transpose();
      }
    }
    EXPECT_GT(inside, 20) << s.kind;
  }
}

TEST(PhantomShapes, InexactDistancesAreConservative) {
  // 1-Lipschitz everywhere: |f(x) - f(y)| <= |x - y|, so |f| never exceeds the true distance.
  std::mt19937_64 rng(8);
  std::normal_distribution<double> n(0, 1);
  for (const auto& s : allShapes()) {
    if (hasExactDistance(s)) continue;
    Vec3 lo, hi;
    bounds(s, &lo, &hi);
    for (int k = 0; k < 20000; ++k) {
      const Vec3 x = randomIn(rng, lo - Vec3::Constant(2), hi + Vec3::Constant(2));
      const Vec3 y = x + 0.3 * Vec3(n(rng), n(rng), n(rng));
      ASSERT_LE(std::abs(signedDistance(s, x) - signedDistance(s, y)), (x - y).norm() + 1e-9)
          << s.kind << " " << x.transpose();
    }
  }
}

TEST(PhantomShapes, FigureOneElevenPairSharesItsTwoSections) {
  const std::map<std::string, double> p{{"inner_radius", 6}, {"outer_radius", 10},
                                        {"gap_deg", 60}, {"height", 20}};
  const auto twisted = make("twisted_cylinder", p), notched = make("notched_torus", p);
  int differ = 0;
  for (double x = -11; x <= 11; x += 0.25)
    for (double y = -11; y <= 11; y += 0.25) {
      for (const double z : {0.0, 20.0})
        ASSERT_EQ(signedDistance(twisted, Vec3(x, y, z)) < 0,
                  signedDistance(notched, Vec3(x, y, z)) < 0)
            << x << " " << y << " " << z;
      differ += (signedDistance(twisted, Vec3(x, y, 10)) < 0) !=
                (signedDistance(notched, Vec3(x, y, 10)) < 0);
    }
  EXPECT_GT(differ, 100);  // between the planes they differ
  // The C at z = 0 has its gap around angle 0; at z = H around angle 180 degrees.
  EXPECT_GT(signedDistance(twisted, Vec3(8, 0, 0)), 0);
  EXPECT_LT(signedDistance(twisted, Vec3(-8, 0, 0)), 0);
  EXPECT_LT(signedDistance(twisted, Vec3(8, 0, 20)), 0);
  EXPECT_GT(signedDistance(twisted, Vec3(-8, 0, 20)), 0);
  EXPECT_EQ(bettiNumbers(twisted), (Betti{1, 0, 0}));
  EXPECT_EQ(bettiNumbers(notched), (Betti{1, 1, 0}));
  EXPECT_FALSE(hasExactDistance(twisted));
}

TEST(PhantomShapes, VesselTreeBranchesOnlyTouchAtJunctions) {
  VesselTreeParams p;
  p.levels = 4;
  p.seed = 17;
  const auto tubes = growVesselTree(p);
  ASSERT_EQ(tubes.size(), 31u);  // 1 + 2 + 4 + 8 + 16
  for (std::size_t i = 0; i < tubes.size(); ++i) {
    EXPECT_GT((tubes[i].b - tubes[i].a).normalized().z(), 0.5);  // grows along +z
    for (std::size_t j = i + 1; j < tubes.size(); ++j) {
      const bool touch = (tubes[i].a - tubes[j].a).norm() < 1e-12 ||
                         (tubes[i].b - tubes[j].a).norm() < 1e-12 ||
                         (tubes[j].b - tubes[i].a).norm() < 1e-12;
      if (touch) continue;
      EXPECT_GT(segmentDistance(tubes[i].a, tubes[i].b, tubes[j].a, tubes[j].b),
                tubes[i].radius + tubes[j].radius)
          << i << " " << j;
    }
  }
  const auto again = growVesselTree(p);
  for (std::size_t i = 0; i < tubes.size(); ++i) EXPECT_EQ(tubes[i].b, again[i].b);
  const auto shape = make("vessel_tree", {{"length", 10}, {"radius", 1}, {"levels", 2}});
  EXPECT_EQ(reach(shape), 0.0);
  EXPECT_DOUBLE_EQ(shape.params.at("nominal_reach"), 1.0 * 0.85 * 0.85);
  EXPECT_EQ(bettiNumbers(shape), (Betti{1, 0, 0}));
}

TEST(PhantomShapes, ValidationNamesTheParameter) {
  auto problem = [](const std::string& kind, std::map<std::string, double> params) {
    PhantomShape s;
    s.kind = kind;
    s.params = std::move(params);
    const auto p = checkPhantomShape(s);
    return p ? p->param : std::string("<none>");
  };
  EXPECT_EQ(problem("sphere", {{"radius", -1}}), "radius");
  EXPECT_EQ(problem("sphere", {}), "radius");
  EXPECT_EQ(problem("cube", {}), "");
  EXPECT_EQ(problem("torus", {{"major_radius", 3}, {"minor_radius", 4}}), "minor_radius");
  EXPECT_EQ(problem("genus2", {{"disk_radius", 20}, {"hole_radius", 5}, {"hole_offset", 6},
                               {"offset_radius", 2}}), "hole_offset");
  EXPECT_EQ(problem("genus2", {{"disk_radius", 20}, {"hole_radius", 2}, {"hole_offset", 8},
                               {"offset_radius", 2.5}}), "hole_radius");
  EXPECT_EQ(problem("two_spheres", {{"radius", 5}, {"separation", 9}}), "separation");
  EXPECT_EQ(problem("hollow_sphere", {{"outer_radius", 5}, {"inner_radius", 5}}), "inner_radius");
  EXPECT_EQ(problem("vessel_tree", {{"length", 10}, {"radius", 1}, {"levels", 2.5}}), "levels");
  EXPECT_EQ(problem("twisted_cylinder", {{"inner_radius", 6}, {"outer_radius", 10},
                                         {"height", 20}, {"gap_deg", 200}}), "gap_deg");
  EXPECT_EQ(problem("sphere", {{"radius", 2}}), "<none>");
}

// ---- slicing patterns ------------------------------------------------------------------------

namespace {
const Vec3 kMin(-10, -8, -6), kMax(12, 8, 6);
ImageSpec image(double px = 0.5) {
  ImageSpec s;
  s.pixel_mm = px;
  return s;
}
/// The image of every pose covers the bounding sphere's projection.
void expectCoversBoundingSphere(const SlicePlan& plan) {
  const Vec3 c = 0.5 * (kMin + kMax);
  const double r = 0.5 * (kMax - kMin).norm();
  for (const Mat4& m : plan.poses) {
    const Plane p = planeOfPose(m);
    const Vec2 q = p.toPlane(c);
    const double w = (plan.width - 1) * plan.pixel_mm, h = (plan.height - 1) * plan.pixel_mm;
    EXPECT_GE(q.x() - r, 0 - 1e-9);
    EXPECT_LE(q.x() + r, w + 1e-9);
    EXPECT_GE(q.y() - r, -1e-9);
    EXPECT_LE(q.y() + r, h + 1e-9);
  }
}
}  // namespace

TEST(PhantomPatterns, MultiaxialStacksAreOrthogonal) {
  SlicingPattern p;
  p.kind = "multiaxial";
  p.counts = {4, 5, 6};
  const SlicePlan plan = planSlices(p, image(), kMin, kMax, 1);
  ASSERT_EQ(plan.poses.size(), 15u);
  for (int i = 0; i < 15; ++i) {
    const int axis = i < 4 ? 0 : i < 9 ? 1 : 2;
    const Plane pl = planeOfPose(plan.poses[i]);
    EXPECT_NEAR(std::abs(pl.normal[axis]), 1.0, 1e-12);
    EXPECT_NEAR((plan.poses[i].block<3, 1>(0, 0).norm()), 0.5, 1e-12);
    EXPECT_NEAR((plan.poses[i].block<3, 1>(0, 0).dot(plan.poses[i].block<3, 1>(0, 1))), 0, 1e-12);
    // Planes lie strictly inside the bounds along their axis.
    EXPECT_GT(pl.origin[axis], kMin[axis]);
    EXPECT_LT(pl.origin[axis], kMax[axis]);
  }
  EXPECT_NEAR(planeOfPose(plan.poses[0]).normal.dot(planeOfPose(plan.poses[4]).normal), 0, 1e-12);
  EXPECT_NEAR(planeOfPose(plan.poses[4]).normal.dot(planeOfPose(plan.poses[9]).normal), 0, 1e-12);
  expectCoversBoundingSphere(plan);
}

TEST(PhantomPatterns, ParallelSpacingPositionsAndTilt) {
  SlicingPattern p;
  p.kind = "parallel";
  p.count = 7;
  p.direction = Vec3(1, 1, 0).normalized();
  p.spacing_mm = 1.5;
  SlicePlan plan = planSlices(p, image(), kMin, kMax, 1);
  ASSERT_EQ(plan.poses.size(), 7u);
  for (int i = 0; i + 1 < 7; ++i) {
    const Plane a = planeOfPose(plan.poses[i]), b = planeOfPose(plan.poses[i + 1]);
    EXPECT_NEAR(a.normal.dot(p.direction), 1.0, 1e-12);
    EXPECT_NEAR(a.signedDistance(b.origin), 1.5, 1e-9);
  }
  expectCoversBoundingSphere(plan);
  p.spacing_mm.reset();
  p.positions_mm = {0.0, 2.5};
  p.direction = Vec3::UnitZ();
  plan = planSlices(p, image(), kMin, kMax, 1);
  ASSERT_EQ(plan.poses.size(), 2u);
  EXPECT_NEAR(plan.poses[1](2, 3), 2.5, 1e-12);
  p.positions_mm.clear();
  p.count = 50;
  p.tilt_deg = 10;
  plan = planSlices(p, image(), kMin, kMax, 1);
  double maxTilt = 0;
  for (const Mat4& m : plan.poses)
    maxTilt = std::max(maxTilt, std::acos(std::min(1.0, planeOfPose(m).normal.z())));
  EXPECT_GT(maxTilt, 5 * M_PI / 180);
  EXPECT_LE(maxTilt, 10 * M_PI / 180 + 1e-9);
}

TEST(PhantomPatterns, FanPlanesShareTheAxis) {
  SlicingPattern p;
  p.kind = "fan";
  p.count = 12;
  p.axis = Vec3(0, 1, 1).normalized();
  const SlicePlan plan = planSlices(p, image(), kMin, kMax, 1);
  ASSERT_EQ(plan.poses.size(), 12u);
  const Vec3 c = 0.5 * (kMin + kMax);
  for (const Mat4& m : plan.poses) {
    const Plane pl = planeOfPose(m);
    EXPECT_NEAR(pl.signedDistance(c), 0, 1e-9);
    EXPECT_NEAR(pl.signedDistance(c + 10 * p.axis), 0, 1e-9);
  }
  // Distinct planes, 15 degrees apart.
  const double a = std::acos(std::abs(
      planeOfPose(plan.poses[0]).normal.dot(planeOfPose(plan.poses[1]).normal)));
  EXPECT_NEAR(a, M_PI / 12, 1e-9);
  expectCoversBoundingSphere(plan);
}

TEST(PhantomPatterns, RandomPlanesCutTheBoundingSphere) {
  SlicingPattern p;
  p.kind = "random";
  p.count = 100;
  const SlicePlan plan = planSlices(p, image(), kMin, kMax, 9);
  ASSERT_EQ(plan.poses.size(), 100u);
  const Vec3 c = 0.5 * (kMin + kMax);
  const double r = 0.5 * (kMax - kMin).norm();
  Vec3 meanAbs = Vec3::Zero();
  for (const Mat4& m : plan.poses) {
    const Plane pl = planeOfPose(m);
    EXPECT_LE(std::abs(pl.signedDistance(c)), r);
    meanAbs += pl.normal.cwiseAbs() / 100.0;
  }
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(meanAbs[k], 0.5, 0.12);  // uniform: E|n_k| = 1/2
  const SlicePlan again = planSlices(p, image(), kMin, kMax, 9);
  EXPECT_EQ(plan.poses[50], again.poses[50]);
  const SlicePlan other = planSlices(p, image(), kMin, kMax, 10);
  EXPECT_NE(plan.poses[50], other.poses[50]);
}

TEST(PhantomPatterns, FreehandSweepIsMonotonicWithSmoothTilt) {
  SlicingPattern p;
  p.kind = "freehand";
  p.count = 300;
  p.tilt_deg = 5;
  p.sector = true;
  ImageSpec im = image(0.2);
  im.width = 160;
  im.height = 120;
  const SlicePlan plan = planSlices(p, im, kMin, kMax, 4);
  ASSERT_EQ(plan.poses.size(), 300u);
  EXPECT_EQ(plan.width, 160);
  ASSERT_TRUE(plan.sector.has_value());
  const Vec3 c = 0.5 * (kMin + kMax);
  const double r = 0.5 * (kMax - kMin).norm();
  const Vec2 mid(0.5 * 159 * 0.2, 0.5 * 119 * 0.2);  // image centre, mm
  double maxTilt = 0;
  for (int i = 0; i + 1 < 300; ++i) {
    const Plane a = planeOfPose(plan.poses[i]), b = planeOfPose(plan.poses[i + 1]);
    EXPECT_TRUE(planesSeparatedInBall(plan.poses[i], plan.poses[i + 1], c, r)) << i;
    EXPECT_GT(a.signedDistance(b.toWorld(mid)), 0) << i;  // image centre ahead
    maxTilt = std::max(maxTilt, std::acos(a.normal.z()));
    EXPECT_LT(std::acos(std::min(1.0, a.normal.dot(b.normal))), 0.01);  // smooth
  }
  EXPECT_GT(maxTilt, 0.5 * M_PI / 180);  // the tilt does drift
  EXPECT_LT(maxTilt, 7.1 * M_PI / 180);
  // The sweep covers the bounds along z.
  EXPECT_LT(planeOfPose(plan.poses.front()).toWorld(mid).z(), kMin.z() + 1);
  EXPECT_GT(planeOfPose(plan.poses.back()).toWorld(mid).z(), kMax.z() - 1);
  // The sector FOV: apex above the image, centre column inside, top corners outside.
  EXPECT_TRUE(plan.sector->contains(80, 60));
  EXPECT_FALSE(plan.sector->contains(0, 0));
}
