// Phantom shapes and slicing patterns (geometry/phantoms/phantom_shape.h, geometry/phantoms/slicing_pattern.h):
// exactness of the signed distances, known values (reach interior / exterior), nearest boundary
// points, bounds, validation, the vessel tree's clearance, its blended junctions (no creases,
// reach bounds that hold, Betti numbers, blend 0 = the union of capsules), two-label shapes, the
// Fig. 1.11 pair's shared sections, and the geometry of every slicing pattern.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "geometry/core/digital_topology.h"
#include "geometry/phantoms/ellipsoid_distance.h"
#include "geometry/phantoms/phantom_shape.h"
#include "geometry/core/plane_of_pose.h"
#include "geometry/phantoms/slicing_pattern.h"
#include "geometry/phantoms/vessel_tree.h"

using namespace xsect;

namespace {

PhantomShape make(const std::string& kind, std::map<std::string, double> params,
                  const Vec3& centre = Vec3::Zero(), const Vec3& euler = Vec3::Zero()) {
  PhantomShape s;
  s.kind = *choiceNamed(kShapeKinds, kind);
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
  v.push_back(make("cup", {{"radius", 10}, {"height", 24}, {"wall", 2}, {"bottom", 3}, {"handle_radius", 6},
                           {"handle_thickness", 3}}, c, e));
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
    ASSERT_TRUE(hasExactDistance(s)) << nameOf(kShapeKinds, s.kind);
    Vec3 lo, hi;
    bounds(s, &lo, &hi);
    lo -= Vec3::Constant(3);
    hi += Vec3::Constant(3);
    const double r = reach(s);
    ASSERT_GT(r, 0) << nameOf(kShapeKinds, s.kind);
    int tested = 0;
    for (int k = 0; k < 20000 && tested < 300; ++k) {
      const Vec3 x = randomIn(rng, lo, hi);
      const double d = signedDistance(s, x);
      if (std::abs(d) > 0.9 * r) continue;  // inside the reach: no medial axis nearby
      ++tested;
      const Vec3 g = gradient(s, x);
      EXPECT_NEAR(g.norm(), 1.0, 1e-4) << nameOf(kShapeKinds, s.kind) << " at " << x.transpose();
      const Vec3 foot = x - d * g.normalized();
      EXPECT_NEAR(signedDistance(s, foot), 0.0, 1e-5) << nameOf(kShapeKinds, s.kind) << " at " << x.transpose();
    }
    EXPECT_GE(tested, 300) << nameOf(kShapeKinds, s.kind);
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
  // Interior / exterior: inner and outer medial axes.
  EXPECT_DOUBLE_EQ(reachInterior(s[0]), 7);
  EXPECT_TRUE(std::isinf(reachExterior(s[0])));  // convex: no outer medial axis
  EXPECT_DOUBLE_EQ(reachInterior(s[1]), 16.0 / 9.0);
  EXPECT_TRUE(std::isinf(reachExterior(s[1])));
  EXPECT_DOUBLE_EQ(reachInterior(s[2]), 3);        // the core circle
  EXPECT_DOUBLE_EQ(reachExterior(s[2]), 7);        // the axis of the hole
  EXPECT_DOUBLE_EQ(reachInterior(s[3]), 2.5);
  EXPECT_DOUBLE_EQ(reachExterior(s[3]), 2.5);
  EXPECT_DOUBLE_EQ(reachInterior(s[4]), 2);        // the middle sphere
  EXPECT_DOUBLE_EQ(reachExterior(s[4]), 6);        // the cavity's centre
  EXPECT_DOUBLE_EQ(reachInterior(s[5]), 5);
  EXPECT_DOUBLE_EQ(reachExterior(s[5]), 2);        // half the gap
}

TEST(PhantomShapes, ClosestBoundaryPointOfExactShapesMatchesTheDistance) {
  std::mt19937_64 rng(21);
  for (const auto& s : exactShapes()) {
    Vec3 lo, hi;
    bounds(s, &lo, &hi);
    for (int k = 0; k < 200; ++k) {
      const Vec3 x = randomIn(rng, lo - Vec3::Constant(3), hi + Vec3::Constant(3));
      const Vec3 p = closestBoundaryPoint(s, x);
      EXPECT_NEAR(signedDistance(s, p), 0.0, 1e-8) << nameOf(kShapeKinds, s.kind);
      EXPECT_NEAR((x - p).norm(), std::abs(signedDistance(s, x)), 1e-6)
          << nameOf(kShapeKinds, s.kind) << " " << x.transpose();
    }
  }
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
            << nameOf(kShapeKinds, s.kind) << " " << x.transpose();
      }
    }
    EXPECT_GT(inside, 20) << nameOf(kShapeKinds, s.kind);
  }
}

/// The cup's voxels (the sign of its distance at voxel centres) have the Betti numbers it
/// declares: one component, one tunnel (the handle), no cavity, in any placement.
TEST(PhantomShapes, CupIsOneComponentWithTheHandlesTunnel) {
  for (const Vec3& e : {Vec3(0, 0, 0), Vec3(10, -20, 30), Vec3(75, 40, -15)}) {
    const PhantomShape cup = make("cup", {{"radius", 10}, {"height", 24}, {"wall", 2}, {"bottom", 3},
                                          {"handle_radius", 6}, {"handle_thickness", 3}}, Vec3(1, 2, 3), e);
    Vec3 lo, hi;
    bounds(cup, &lo, &hi);
    GridSpec g;
    g.voxel = 0.4;
    g.origin = lo - Vec3::Constant(1);
    for (int a = 0; a < 3; ++a) g.dims[std::size_t(a)] = int(std::ceil((hi[a] - lo[a] + 2) / g.voxel)) + 1;
    std::vector<std::uint8_t> in(std::size_t(g.count()));
    for (int k = 0; k < g.dims[2]; ++k)
      for (int j = 0; j < g.dims[1]; ++j)
        for (int i = 0; i < g.dims[0]; ++i) in[std::size_t(g.index(i, j, k))] = signedDistance(cup, g.centre(i, j, k)) < 0;
    EXPECT_EQ(voxelBetti(in, g), bettiNumbers(cup)) << e.transpose();
  }
  EXPECT_EQ(bettiNumbers(make("cup", {{"radius", 10}, {"height", 24}, {"wall", 2}, {"bottom", 3},
                                      {"handle_radius", 6}, {"handle_thickness", 3}}, Vec3::Zero(), Vec3::Zero())),
            (Betti{1, 1, 0}));
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
          << nameOf(kShapeKinds, s.kind) << " " << x.transpose();
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
  const auto shape =
      make("vessel_tree", {{"length", 10}, {"radius", 1}, {"levels", 2}, {"blend_mm", 0}});
  EXPECT_EQ(reach(shape), 0.0);  // creases at the junctions
  EXPECT_EQ(reachExterior(shape), 0.0);
  EXPECT_DOUBLE_EQ(reachInterior(shape), 1.0 * 0.85 * 0.85);
  EXPECT_DOUBLE_EQ(shape.params.at("nominal_reach"), 1.0 * 0.85 * 0.85);
  EXPECT_EQ(bettiNumbers(shape), (Betti{1, 0, 0}));
  const auto smooth = make("vessel_tree", {{"length", 10}, {"radius", 1}, {"levels", 2}});
  EXPECT_EQ(smooth.params.at("blend_mm"), 0.5);  // smooth by default
  EXPECT_GT(reach(smooth), 0.0);
}

// ---- the blended vessel tree -------------------------------------------------------------------

namespace {

/// Two blended trees: the default fillet (0.5 mm) on thin 30-degree branches, and a wide fillet
/// (2 mm) on 45-degree branches (the vessel-tree-sparse phantom), both placed off the origin.
std::vector<PhantomShape> blendedTrees() {
  const Vec3 c(1, 2, 3), e(10, -20, 30);
  return {make("vessel_tree", {{"length", 10}, {"radius", 1}, {"levels", 3}}, c, e),
          make("vessel_tree", {{"length", 20}, {"radius", 1.5}, {"levels", 2},
                               {"branch_angle_deg", 45}, {"blend_mm", 2}}, c, e),
          // A fillet 12 times thinner than the tubes: sampling it at blend_mm / 6 would take
          // about 480,000 points a junction, past the bound the reach's search keeps to
          // (vessel_tree.cpp, kJunctionStartBudget); its bounds must hold all the same.
          make("vessel_tree", {{"length", 10}, {"radius", 1}, {"levels", 1},
                               {"branch_angle_deg", 40}, {"blend_mm", 0.08}}, c, e)};
}

/// Boundary points near the junctions (where the blends act): nearest boundary points of random
/// points within 1.5 mm of a junction point.
std::vector<Vec3> junctionBoundaryPoints(const PhantomShape& s, int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  std::vector<Vec3> out;
  while (int(out.size()) < n) {
    const auto& J = s.junctions[rng() % s.junctions.size()];
    if (J.children.empty()) continue;
    const Vec3 x = s.centre + s.rotation * (s.tubes[J.parent].b + Vec3(u(rng), u(rng), u(rng)));
    out.push_back(closestBoundaryPoint(s, x));
  }
  return out;
}

/// Nearest boundary point (brute force) among dense boundary samples: Newton projections of a
/// grid of spacing h over the box [lo, hi].
std::vector<Vec3> denseBoundary(const PhantomShape& s, const Vec3& lo, const Vec3& hi, double h) {
  std::vector<Vec3> out;
  for (double x = lo.x(); x <= hi.x(); x += h)
    for (double y = lo.y(); y <= hi.y(); y += h)
      for (double z = lo.z(); z <= hi.z(); z += h) {
        Vec3 p(x, y, z);
        if (std::abs(signedDistance(s, p)) > 1.5 * h) continue;
        for (int it = 0; it < 30; ++it) {
          const double f = signedDistance(s, p);
          if (std::abs(f) < 1e-12) break;
          const Vec3 g = gradient(s, p);
          p -= f / g.squaredNorm() * g;
        }
        if (std::abs(signedDistance(s, p)) < 1e-9) out.push_back(p);
      }
  return out;
}

}  // namespace

TEST(PhantomShapes, BlendZeroIsTheUnionOfCapsules) {
  VesselTreeParams p;
  p.length = 10;
  p.radius = 1;
  p.levels = 3;
  const auto grown = growVesselTree(p);
  const auto s =
      make("vessel_tree", {{"length", 10}, {"radius", 1}, {"levels", 3}, {"blend_mm", 0}},
           Vec3(1, 2, 3), Vec3(10, -20, 30));
  ASSERT_EQ(s.tubes.size(), grown.size());
  for (std::size_t i = 0; i < grown.size(); ++i) {
    EXPECT_EQ(s.tubes[i].a, grown[i].a);
    EXPECT_EQ(s.tubes[i].b, grown[i].b);
  }
  std::mt19937_64 rng(4);
  Vec3 lo, hi;
  bounds(s, &lo, &hi);
  for (int k = 0; k < 5000; ++k) {
    const Vec3 x = randomIn(rng, lo - Vec3::Constant(2), hi + Vec3::Constant(2));
    const Vec3 q = s.rotation.transpose() * (x - s.centre);
    double capsules = INFINITY;
    for (const auto& t : s.tubes) {
      const Vec3 d = t.b - t.a;
      const double u = std::clamp((q - t.a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      capsules = std::min(capsules, (t.a + u * d - q).norm() - t.radius);
    }
    EXPECT_EQ(signedDistance(s, x), capsules) << x.transpose();
  }
  EXPECT_FALSE(hasExactDistance(s));
}

TEST(PhantomShapes, BlendedVesselTreeHasNoCrease) {
  // On a C^{1,1} surface the normal turns by at most |p - p'| / reach between nearby boundary
  // points; across a crease it turns by a finite angle however close they are.
  auto maxTurnRate = [](const PhantomShape& s, const std::vector<Vec3>& pts, double eps) {
    double rate = 0;
    for (const Vec3& p : pts) {
      const Vec3 n = gradient(s, p).normalized();
      const Vec3 t1 = n.unitOrthogonal(), t2 = n.cross(t1);
      for (int a = 0; a < 8; ++a) {
        const Vec3 dir = std::cos(a * M_PI / 4) * t1 + std::sin(a * M_PI / 4) * t2;
        const Vec3 q = closestBoundaryPoint(s, p + eps * dir);
        const double d = (q - p).norm();
        if (d < 0.1 * eps) continue;
        rate = std::max(rate, (gradient(s, q).normalized() - n).norm() / d);
      }
    }
    return rate;
  };
  for (const auto& s : blendedTrees()) {
    const double r = reach(s);
    ASSERT_GT(r, 0.0);
    const auto pts = junctionBoundaryPoints(s, 300, 5);
    for (const double eps : {1e-2, 1e-3}) {
      const double rate = maxTurnRate(s, pts, eps);
      EXPECT_LT(rate, 1.05 / r) << "blend " << s.params.at("blend_mm") << " eps " << eps;
    }
  }
  // The same probe finds the creases of the plain union of capsules.
  const auto creased = make("vessel_tree", {{"length", 10}, {"radius", 1}, {"levels", 3},
                                            {"blend_mm", 0}}, Vec3(1, 2, 3), Vec3(10, -20, 30));
  EXPECT_GT(maxTurnRate(creased, junctionBoundaryPoints(creased, 300, 5), 1e-3), 50.0);
}

TEST(PhantomShapes, BlendedVesselTreeReachBoundsHold) {
  // From a boundary point p with outer normal n, the points p - t n (0 < t < reach_i) and
  // p + t n (0 < t < reach_e) have p as their nearest boundary point.
  for (const auto& s : blendedTrees()) {
    const double ri = reachInterior(s), re = reachExterior(s);
    ASSERT_GT(ri, 0.0);
    ASSERT_GT(re, 0.0);
    EXPECT_LE(ri, s.params.at("nominal_reach"));  // never above the thinnest tube's radius
    std::vector<Vec3> pts = junctionBoundaryPoints(s, 1500, 7);
    std::mt19937_64 rng(9);
    Vec3 lo, hi;
    bounds(s, &lo, &hi);
    while (pts.size() < 2500) {  // and anywhere on the tree
      const Vec3 x = randomIn(rng, lo, hi);
      if (std::abs(signedDistance(s, x)) < 1.0) pts.push_back(closestBoundaryPoint(s, x));
    }
    int tooFar = 0;
    for (const Vec3& p : pts) {
      const Vec3 n = gradient(s, p).normalized();
      EXPECT_LT((closestBoundaryPoint(s, p - 0.9 * ri * n) - p).norm(), 1e-3)
          << "inside, from " << p.transpose();
      EXPECT_LT((closestBoundaryPoint(s, p + 0.9 * re * n) - p).norm(), 1e-3)
          << "outside, from " << p.transpose();
      tooFar += (closestBoundaryPoint(s, p + 2.0 * re * n) - p).norm() > 1e-2;
    }
    EXPECT_GT(tooFar, 0) << "reach_e is not within a factor 2 of tight";
  }
}

TEST(PhantomShapes, BlendedVesselTreeClosestPointMatchesBruteForce) {
  const auto s = blendedTrees()[1];
  const auto& J = s.junctions[0];  // the root's junction, the trunk's end
  const Vec3 c = s.centre + s.rotation * s.tubes[J.parent].b;
  const std::vector<Vec3> dense =
      denseBoundary(s, c - Vec3::Constant(3.5), c + Vec3::Constant(3.5), 0.05);
  ASSERT_GT(dense.size(), 10000u);
  std::mt19937_64 rng(13);
  for (int k = 0; k < 150; ++k) {
    const Vec3 x = randomIn(rng, c - Vec3::Constant(2), c + Vec3::Constant(2));
    const double d = (x - closestBoundaryPoint(s, x)).norm();
    double brute = INFINITY;
    for (const Vec3& p : dense) brute = std::min(brute, (p - x).norm());
    EXPECT_LE(d, brute + 1e-9) << x.transpose();
    // The dense samples are within ~h = 0.05 mm of every boundary point, sideways.
    EXPECT_LE(brute * brute, d * d + 0.05 * 0.05) << x.transpose();
    EXPECT_GE(d + 1e-12, std::abs(signedDistance(s, x))) << x.transpose();  // sdf is conservative
  }
}

TEST(PhantomShapes, BlendedVesselTreeIsContractible) {
  // Voxel Betti numbers of the solid sampled at 0.1 mm (a quarter of its reach, ~0.4 mm).
  const auto s = make("vessel_tree", {{"length", 6}, {"radius", 0.6}, {"levels", 2},
                                      {"blend_mm", 1}, {"branch_angle_deg", 45}});
  ASSERT_GT(reach(s), 0.35);
  Vec3 lo, hi;
  bounds(s, &lo, &hi);
  GridSpec g;
  g.voxel = 0.1;
  g.origin = lo - Vec3::Constant(0.1);
  for (int c = 0; c < 3; ++c) g.dims[c] = int(std::ceil((hi[c] - lo[c]) / g.voxel)) + 5;
  std::vector<std::uint8_t> in(std::size_t(g.count()));
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i)
        in[std::size_t(g.index(i, j, k))] = signedDistance(s, g.centre(i, j, k)) < 0;
  EXPECT_EQ(voxelBetti(in, g), (Betti{1, 0, 0}));
  EXPECT_EQ(bettiNumbers(s), (Betti{1, 0, 0}));
}

TEST(PhantomShapes, VesselTreeBlendKeepsJunctionsApart) {
  // Tubes that share no junction keep 3 blend widths between their capsules.
  const auto s = blendedTrees()[0];
  const double k = s.params.at("blend_mm");
  for (std::size_t i = 0; i < s.tubes.size(); ++i)
    for (std::size_t j = i + 1; j < s.tubes.size(); ++j) {
      bool adjacent = false;
      for (const auto& J : s.junctions) {
        std::vector<int> m{J.parent};
        m.insert(m.end(), J.children.begin(), J.children.end());
        adjacent = adjacent || (std::count(m.begin(), m.end(), int(i)) &&
                                std::count(m.begin(), m.end(), int(j)));
      }
      if (adjacent) continue;
      EXPECT_GT(segmentDistance(s.tubes[i].a, s.tubes[i].b, s.tubes[j].a, s.tubes[j].b) -
                    s.tubes[i].radius - s.tubes[j].radius,
                3 * k)
          << i << " " << j;
    }
  EXPECT_EQ(s.junctions.size(), 7u);  // one per tube with children
}

TEST(PhantomShapes, LabelSplitTorusHalves) {
  auto torus = make("torus", {{"major_radius", 10}, {"minor_radius", 3}}, Vec3(1, 2, 3),
                    Vec3(20, 10, 0));
  torus.label_split = PhantomShape::LabelSplit{Vec3::Zero(), Vec3::UnitX()};  // through the axis
  const Eigen::Matrix3d R = torus.rotation;
  EXPECT_EQ(materialLabel(torus, torus.centre + R * Vec3(-10, 0, 0)), 1);
  EXPECT_EQ(materialLabel(torus, torus.centre + R * Vec3(10, 0, 0)), 2);
  EXPECT_EQ(materialLabel(torus, torus.centre), 0);  // the hole
  EXPECT_EQ(materialLabel(torus, torus.centre + R * Vec3(0, 20, 0)), 0);
  const auto halves = labelBettiNumbers(torus);
  ASSERT_EQ(halves.size(), 2u);
  EXPECT_EQ(halves.at(1), (Betti{1, 0, 0}));  // two C-shaped halves
  EXPECT_EQ(halves.at(2), (Betti{1, 0, 0}));
  torus.label_split = PhantomShape::LabelSplit{Vec3::Zero(), Vec3::UnitZ()};  // the equator
  const auto rings = labelBettiNumbers(torus);
  EXPECT_EQ(rings.at(1), (Betti{1, 1, 0}));  // two half tori, each a solid torus
  EXPECT_EQ(rings.at(2), (Betti{1, 1, 0}));
  torus.label_split.reset();
  EXPECT_TRUE(labelBettiNumbers(torus).empty());
  EXPECT_EQ(materialLabel(torus, torus.centre + R * Vec3(10, 0, 0)), 1);
}

TEST(PhantomShapes, ValidationNamesTheParameter) {
  auto problem = [](const std::string& kind, std::map<std::string, double> params) {
    PhantomShape s;
    s.kind = *choiceNamed(kShapeKinds, kind);
    s.params = std::move(params);
    const auto p = checkPhantomShape(s);
    return p ? p->param : std::string("<none>");
  };
  EXPECT_EQ(problem("sphere", {{"radius", -1}}), "radius");
  EXPECT_EQ(problem("sphere", {}), "radius");
  EXPECT_FALSE(choiceNamed(kShapeKinds, "cube"));  // an unknown kind is refused where it is read
  EXPECT_EQ(problem("torus", {{"major_radius", 3}, {"minor_radius", 4}}), "minor_radius");
  EXPECT_EQ(problem("genus2", {{"disk_radius", 20}, {"hole_radius", 5}, {"hole_offset", 6},
                               {"offset_radius", 2}}), "hole_offset");
  EXPECT_EQ(problem("genus2", {{"disk_radius", 20}, {"hole_radius", 2}, {"hole_offset", 8},
                               {"offset_radius", 2.5}}), "hole_radius");
  EXPECT_EQ(problem("two_spheres", {{"radius", 5}, {"separation", 9}}), "separation");
  EXPECT_EQ(problem("hollow_sphere", {{"outer_radius", 5}, {"inner_radius", 5}}), "inner_radius");
  EXPECT_EQ(problem("vessel_tree", {{"length", 10}, {"radius", 1}, {"levels", 2.5}}), "levels");
  EXPECT_EQ(problem("vessel_tree", {{"length", 10}, {"radius", 1}, {"blend_mm", -1}}), "blend_mm");
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

TEST(PhantomShapesPatterns, MultiaxialStacksAreOrthogonal) {
  SlicingPattern p;
  p.kind = PatternKind::multiaxial;
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

TEST(PhantomShapesPatterns, ParallelSpacingPositionsAndTilt) {
  SlicingPattern p;
  p.kind = PatternKind::parallel;
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

TEST(PhantomShapesPatterns, FanPlanesShareTheAxis) {
  SlicingPattern p;
  p.kind = PatternKind::fan;
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

TEST(PhantomShapesPatterns, RandomPlanesCutTheBoundingSphere) {
  SlicingPattern p;
  p.kind = PatternKind::random;
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

TEST(PhantomShapesPatterns, FreehandSweepIsMonotonicWithSmoothTilt) {
  SlicingPattern p;
  p.kind = PatternKind::freehand;
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
