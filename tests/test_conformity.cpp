// Conformity along plane intersections (issue 5): traces on common lines, their disagreement,
// consensus modes, and the local exact edits that make two planes' sections agree.
#include <gtest/gtest.h>

#include <limits>

#include <tbb/global_control.h>

#include <random>

#include "geometry/conformity/conformity_enforcement.h"
#include "geometry/arrangement/plane_pair_traces.h"
#include "geometry/core/polygon.h"
#include "section_fixtures.h"
#include "segmentation/field_of_view.h"

namespace xsect {
namespace {

using test::axisPlane;
using test::circle;

CuttingPlane planeWith(int axis, double offset, std::vector<Section> sections, int slice) {
  CuttingPlane cp;
  cp.slice = slice;
  cp.plane = axisPlane(axis, offset);
  cp.sections = std::move(sections);
  cp.extent = {Vec2(-50, -50), Vec2(50, 50)};
  return cp;
}

ConformityParams averaging() {
  ConformityParams p;
  p.mode = ConsensusMode::average;
  return p;
}

Section disk(const Vec2& c, double r, int n = 64) { return Section{circle(c, r, n), {}, 1}; }
Section annulus(const Vec2& c, double ro, double ri, int n = 64) {
  return Section{circle(c, ro, n), {circle(c, ri, n, false)}, 1};
}

/// Plane z = 0 (u = x, v = y) and plane x = 0 (u = y, v = z): their common line is the y axis.
std::vector<CuttingPlane> crossPair(std::vector<Section> inZ, std::vector<Section> inX) {
  return {planeWith(2, 0.0, std::move(inZ), 0), planeWith(0, 0.0, std::move(inX), 1)};
}

/// The trace on the y axis, as y intervals, of the sections of plane `i`.
Trace yTrace(const std::vector<CuttingPlane>& planes, int i) {
  CommonLine y;
  y.direction = Vec3::UnitY();
  return sectionsTrace(planes[std::size_t(i)].sections, lineInPlane(planes[std::size_t(i)].plane, y));
}

void expectTrace(const Trace& t, const std::vector<std::pair<double, double>>& want, double tol) {
  ASSERT_EQ(t.size(), want.size());
  for (std::size_t k = 0; k < t.size(); ++k) {
    EXPECT_NEAR(t[k].t0, want[k].first, tol) << k;
    EXPECT_NEAR(t[k].t1, want[k].second, tol) << k;
  }
}

/// Every vertex of `before` farther than `band` from the line of `pair` is still a vertex of
/// `after` (the edit is local).
void expectUnchangedAwayFromLine(const CuttingPlane& before, const CuttingPlane& after,
                                 const CommonLine& line, double band) {
  const PlaneLine l = lineInPlane(before.plane, line);
  const std::vector<Vec2> kept = contourSamples(after.sections, std::numeric_limits<double>::infinity());
  int far = 0;
  for (const Vec2& p : contourSamples(before.sections, std::numeric_limits<double>::infinity())) {
    const Vec2 q = p - l.o;
    if (std::abs(l.d.x() * q.y() - l.d.y() * q.x()) <= band + 1e-9) continue;
    ++far;
    bool found = false;
    for (const Vec2& k : kept) found = found || (k - p).norm() < 1e-12;
    EXPECT_TRUE(found) << "vertex (" << p.x() << ", " << p.y() << ") moved";
  }
  EXPECT_GT(far, 0);
  // ...and every vertex that is new lies within the band.
  for (const Section& s : after.sections)
    for (const Vec2& p : s.outer) {
      bool old = false;
      for (const Section& t : before.sections)
        for (const Vec2& q : t.outer) old = old || (q - p).norm() < 1e-12;
      const Vec2 q = p - l.o;
      if (!old) EXPECT_LE(std::abs(l.d.x() * q.y() - l.d.y() * q.x()), band + 1e-9);
    }
}

TEST(Conformity, TracesOfRingsWithHolesAndTangency) {
  const auto planes = crossPair({annulus({0, 0}, 10, 4)}, {});
  expectTrace(yTrace(planes, 0), {{-10, -4}, {4, 10}}, 1e-12);
  // A circle touching the y axis at one vertex has an empty trace (no interval of length > 0).
  const auto tangent = crossPair({disk({10, 0}, 10)}, {});
  EXPECT_TRUE(yTrace(tangent, 0).empty());
  // ...and one crossing it has the chord.
  const auto chord = crossPair({disk({9, 0}, 10)}, {});
  expectTrace(yTrace(chord, 0), {{-std::sqrt(19.0), std::sqrt(19.0)}}, 0.05);
}

TEST(Conformity, IntervalAlgebraAndAverage) {
  const Trace a{{0, 4}, {6, 10}}, b{{1, 5}, {20, 22}}, all{{-100, 100}};
  expectTrace(intersectTraces(a, b), {{1, 4}}, 0);
  expectTrace(uniteTraces(a, b), {{0, 5}, {6, 10}, {20, 22}}, 0);
  expectTrace(subtractTraces(a, b), {{0, 1}, {6, 10}}, 0);
  const TraceDisagreement d = traceDisagreement(a, b, all);
  EXPECT_NEAR(d.symmetric_difference_mm, 1 + 1 + 4 + 2, 1e-12);
  EXPECT_NEAR(d.max_endpoint_mismatch_mm, 4, 1e-12);
  // Corresponding intervals average their endpoints.
  expectTrace(averageTrace({{0, 4}}, {{1, 6}}, all), {{0.5, 5}}, 1e-12);
  // A gap without counterpart closes where the other trace is deeper inside than the gap is wide.
  expectTrace(averageTrace({{0, 10}, {20, 30}}, {{1, 29}}, all), {{0.5, 29.5}}, 1e-12);
  // Intervals that do not overlap have no counterpart: an interval loses where it is shallower
  // than its distance to the other trace's nearest endpoint, here everywhere.
  expectTrace(averageTrace({{6, 10}}, {{1, 5}}, all), {}, 1e-12);
  // Endpoints on the common region's boundary are not object boundaries.
  expectTrace(averageTrace({{0, 4}}, {{-5, 5}}, {{0, 10}}), {{0, 4.5}}, 1e-12);
}

TEST(Conformity, AveragedEndpointsBecomeSharedVerticesAndTheEditIsLocal) {
  // z = 0: disk of radius 10 (trace [-10, 10]); x = 0: disk of radius 9 centred at y = 0.5
  // (trace [-8.5, 9.5]).
  const auto planes = crossPair({disk({0, 0}, 10)}, {disk({0.5, 0}, 9)});
  const PlanePairSearch found = planePairTraces(planes, 5.0);
  ASSERT_EQ(found.pairs.size(), 1u);
  const PlanePairTraces& p = found.pairs[0];
  EXPECT_NEAR(p.disagreement.symmetric_difference_mm, 2.0, 1e-9);
  EXPECT_NEAR(p.disagreement.max_endpoint_mismatch_mm, 1.5, 1e-9);
  EXPECT_NEAR(p.line.angle_deg, 90, 1e-9);

  const ConformityParams params = averaging();
  const ConformityEnforcement e = enforceConformity(planes, found.pairs, params);
  ASSERT_TRUE(e.corrections[0].applied);
  EXPECT_FALSE(e.corrections[0].over_max);
  EXPECT_NEAR(e.corrections[0].correction_a_mm, 0.75, 1e-9);
  EXPECT_NEAR(e.corrections[0].correction_b_mm, 0.75, 1e-9);
  expectTrace(yTrace(e.planes, 0), {{-9.25, 9.75}}, 1e-9);
  expectTrace(yTrace(e.planes, 1), {{-9.25, 9.75}}, 1e-9);
  const auto after = retrace(found.pairs, e.planes);
  EXPECT_LE(after[0].disagreement.symmetric_difference_mm, 1e-6);
  // The consensus endpoints are vertices of both polygons, the same world points.
  for (const double y : {-9.25, 9.75})
    for (const CuttingPlane& cp : e.planes) {
      const Vec2 q = cp.plane.toPlane(Vec3(0, y, 0));
      double nearest = 1e9;
      for (const Section& s : cp.sections)
        for (const Vec2& v : s.outer) nearest = std::min(nearest, (v - q).norm());
      EXPECT_LT(nearest, 1e-12) << "plane " << cp.slice << ", y = " << y;
    }
  // Local: every vertex farther than the band from the line is where it was.
  EXPECT_GT(e.bumps, 0);
  EXPECT_EQ(e.rhombi_added + e.rhombi_removed, 0) << "a pure endpoint move needs no Boolean edit";
  for (int i = 0; i < 2; ++i)
    expectUnchangedAwayFromLine(planes[std::size_t(i)], e.planes[std::size_t(i)], p.line, params.band_mm);
  EXPECT_EQ(e.planes[0].sections.size(), 1u);
  EXPECT_EQ(e.planes[1].sections.size(), 1u);
}

TEST(Conformity, IntersectionAndUnionModes) {
  const auto planes = crossPair({disk({0, 0}, 10)}, {disk({0.5, 0}, 9)});
  const PlanePairSearch found = planePairTraces(planes, 5.0);
  for (const auto& [mode, lo, hi] : {std::tuple{ConsensusMode::intersection, -8.5, 9.5},
                                     std::tuple{ConsensusMode::union_, -10.0, 10.0}}) {
    ConformityParams params;
    params.mode = mode;
    const ConformityEnforcement e = enforceConformity(planes, found.pairs, params);
    for (int i = 0; i < 2; ++i) expectTrace(yTrace(e.planes, i), {{lo, hi}}, 1e-9);
  }
}

TEST(Conformity, LineThroughAHole) {
  const auto planes = crossPair({annulus({0, 0}, 10, 4)}, {annulus({0, 0}, 10.4, 5)});
  const PlanePairSearch found = planePairTraces(planes, 5.0);
  ASSERT_EQ(found.pairs.size(), 1u);
  EXPECT_NEAR(found.pairs[0].disagreement.symmetric_difference_mm, 0.4 * 2 + 1.0 * 2, 1e-9);
  const ConformityEnforcement e = enforceConformity(planes, found.pairs, averaging());
  for (int i = 0; i < 2; ++i) {
    expectTrace(yTrace(e.planes, i), {{-10.2, -4.5}, {4.5, 10.2}}, 1e-9);
    ASSERT_EQ(e.planes[std::size_t(i)].sections.size(), 1u);
    EXPECT_EQ(e.planes[std::size_t(i)].sections[0].holes.size(), 1u) << "the hole stays a hole";
  }
}

TEST(Conformity, SectionAbsentFromOnePlaneAlongTheLine) {
  // x = 0 holds a section far from the y axis: along the line it sees nothing.
  const auto planes = crossPair({disk({0, 0}, 3)}, {disk({0, 20}, 3)});
  const PlanePairSearch found = planePairTraces(planes, 5.0);
  ASSERT_EQ(found.pairs.size(), 1u);
  EXPECT_NEAR(found.pairs[0].disagreement.max_endpoint_mismatch_mm, 6.0, 1e-9);
  // Default: a 6 mm correction exceeds max_correction_mm (5): reported, nothing changes.
  const ConformityEnforcement kept = enforceConformity(planes, found.pairs, {});
  EXPECT_TRUE(kept.corrections[0].over_max);
  EXPECT_FALSE(kept.corrections[0].applied);
  EXPECT_EQ(kept.planes_edited, 0);
  // Union: the empty plane gains the missing piece; intersection: the other loses it.
  ConformityParams params;
  params.max_correction_mm = 10;
  params.mode = ConsensusMode::union_;
  const ConformityEnforcement u = enforceConformity(planes, found.pairs, params);
  expectTrace(yTrace(u.planes, 1), {{-3, 3}}, 1e-9);
  EXPECT_EQ(u.planes[1].sections.size(), 2u);
  params.mode = ConsensusMode::intersection;
  const ConformityEnforcement n = enforceConformity(planes, found.pairs, params);
  EXPECT_TRUE(yTrace(n.planes, 0).empty());
  EXPECT_TRUE(yTrace(n.planes, 1).empty());
}

TEST(Conformity, TangentSection) {
  // z = 0 touches the y axis at one vertex (empty trace); x = 0 crosses it over [-0.5, 0.5].
  const auto planes = crossPair({disk({10, 0}, 10)}, {disk({0, 0}, 0.5)});
  const PlanePairSearch found = planePairTraces(planes, 5.0);
  ASSERT_EQ(found.pairs.size(), 1u);
  EXPECT_NEAR(found.pairs[0].disagreement.symmetric_difference_mm, 1.0, 1e-9);
  const ConformityEnforcement e = enforceConformity(planes, found.pairs, averaging());
  EXPECT_TRUE(e.corrections[0].applied);
  EXPECT_TRUE(yTrace(e.planes, 0).empty());
  EXPECT_TRUE(yTrace(e.planes, 1).empty());
  EXPECT_EQ(e.planes[0].sections[0].outer, planes[0].sections[0].outer) << "the tangent section is kept";
  // Both tangent, nothing to do.
  const auto both = crossPair({disk({10, 0}, 10)}, {disk({0, 10}, 10)});
  EXPECT_TRUE(planePairTraces(both, 5.0).pairs.empty());
}

/// Three orthogonal planes through a ball whose sections are each a little off: three lines,
/// each plane crossed by two of them, handled together.
std::vector<CuttingPlane> threeJitteredDisks(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, 0.4);
  std::vector<CuttingPlane> planes;
  for (int axis = 0; axis < 3; ++axis)
    planes.push_back(planeWith(axis, n(rng), {annulus({n(rng), n(rng)}, 10 + n(rng), 3 + n(rng), 97)}, axis));
  return planes;
}

TEST(Conformity, SeveralLinesThroughOnePlaneAgreeAfterEnforcement) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const auto planes = threeJitteredDisks(seed);
    const PlanePairSearch found = planePairTraces(planes, 5.0);
    ASSERT_EQ(found.pairs.size(), 3u);
    double before = 0;
    for (const auto& p : found.pairs) before = std::max(before, p.disagreement.symmetric_difference_mm);
    EXPECT_GT(before, 0.05);
    const ConformityEnforcement e = enforceConformity(planes, found.pairs, averaging());
    for (const auto& p : retrace(found.pairs, e.planes))
      EXPECT_LE(p.disagreement.symmetric_difference_mm, 1e-6) << "seed " << seed << " pair " << p.a << "-" << p.b;
    for (const CuttingPlane& cp : e.planes) {
      EXPECT_EQ(cp.sections.size(), 1u);
      EXPECT_EQ(cp.sections[0].holes.size(), 1u);
    }
  }
}

TEST(Conformity, EnforcingAgreeingSectionsChangesNothing) {
  // Identical disks whose vertices lie on the common line: they agree already.
  const auto agree = crossPair({disk({0, 0}, 10)}, {disk({0, 0}, 10)});
  const PlanePairSearch found = planePairTraces(agree, 5.0);
  ASSERT_EQ(found.pairs.size(), 1u);
  EXPECT_LE(found.pairs[0].disagreement.symmetric_difference_mm, 1e-9);
  const ConformityEnforcement e = enforceConformity(agree, found.pairs, averaging());
  EXPECT_EQ(e.planes_edited, 0);
  for (int i = 0; i < 2; ++i) EXPECT_EQ(e.planes[std::size_t(i)].sections[0].outer, agree[std::size_t(i)].sections[0].outer);
  // Enforcing twice: the second pass finds nothing to do.
  const auto planes = threeJitteredDisks(7);
  const PlanePairSearch f1 = planePairTraces(planes, 5.0);
  const ConformityEnforcement once = enforceConformity(planes, f1.pairs, averaging());
  const ConformityEnforcement twice = enforceConformity(once.planes, planePairTraces(once.planes, 5.0).pairs, averaging());
  EXPECT_EQ(twice.planes_edited, 0);
  EXPECT_EQ(twice.rounds, 0);
  for (std::size_t i = 0; i < planes.size(); ++i) {
    ASSERT_EQ(twice.planes[i].sections.size(), once.planes[i].sections.size());
    for (std::size_t s = 0; s < once.planes[i].sections.size(); ++s) {
      EXPECT_EQ(twice.planes[i].sections[s].outer, once.planes[i].sections[s].outer);
      EXPECT_EQ(twice.planes[i].sections[s].holes, once.planes[i].sections[s].holes);
    }
  }
}

TEST(Conformity, OnlyWhereBothPlanesObserved) {
  // Plane x = 0's image covers y in [0, 50] only: the part of the line at y < 0 is not compared.
  auto planes = crossPair({disk({0, 0}, 10)}, {disk({0.5, 0}, 9)});
  planes[1].extent = {Vec2(0, -50), Vec2(50, 50)};
  const PlanePairSearch found = planePairTraces(planes, 5.0);
  ASSERT_EQ(found.pairs.size(), 1u);
  EXPECT_NEAR(found.pairs[0].disagreement.symmetric_difference_mm, 0.5, 1e-9);
  const ConformityEnforcement e = enforceConformity(planes, found.pairs, averaging());
  expectTrace(yTrace(e.planes, 0), {{-10, 9.75}}, 1e-9);
  // A field of view narrows the observed region the same way.
  planes[1].extent = {Vec2(-50, -50), Vec2(50, 50)};
  planes[1].field_of_view = {Ring{{0, -50}, {50, -50}, {50, 50}, {0, 50}}};
  EXPECT_NEAR(planePairTraces(planes, 5.0).pairs[0].disagreement.symmetric_difference_mm, 0.5, 1e-9);
  // Nearly parallel planes are counted, not measured.
  planes[1].plane = axisPlane(2, 0.0);
  const double a = 2.0 * M_PI / 180.0;
  planes[1].plane.normal = Vec3(0, -std::sin(a), std::cos(a));
  planes[1].plane.v = Vec3(0, std::cos(a), std::sin(a));
  const PlanePairSearch near = planePairTraces(planes, 5.0);
  EXPECT_TRUE(near.pairs.empty());
  EXPECT_EQ(near.pairs_near_parallel, 1);
}

}  // namespace
}  // namespace xsect

namespace xsect {
namespace {

TEST(Conformity, FieldOfViewRingsBoundTheMask) {
  cv::Mat mask(40, 60, CV_8U, cv::Scalar(0));
  mask(cv::Rect(10, 5, 30, 20)).setTo(255);  // columns 10-39, rows 5-24
  const std::vector<Ring> rings = fieldOfViewRings(mask, Vec2(0.5, 0.25));
  ASSERT_EQ(rings.size(), 1u);
  // The 0.5 iso-line between pixel centres: columns 9.5-39.5 (x 4.75-19.75 mm), rows 4.5-24.5
  // (y 1.125-6.125 mm), corners cut by the marching squares.
  const Eigen::AlignedBox2d b = ringBounds(rings[0]);
  EXPECT_NEAR(b.min().x(), 4.75, 1e-6);
  EXPECT_NEAR(b.max().x(), 19.75, 1e-6);
  EXPECT_NEAR(b.min().y(), 1.125, 1e-6);
  EXPECT_NEAR(b.max().y(), 6.125, 1e-6);
  EXPECT_GT(signedArea(rings[0]), 0);
  EXPECT_NEAR(signedArea(rings[0]), 15.0 * 5.0, 0.5);
  EXPECT_TRUE(fieldOfViewRings(cv::Mat(), Vec2(1, 1)).empty());
  EXPECT_TRUE(fieldOfViewRings(cv::Mat(8, 8, CV_8U, cv::Scalar(1)), Vec2(1, 1)).empty()) << "all observed";
}

}  // namespace
}  // namespace xsect

// Regressions found by an independent review: edits of one line must not change another line's
// trace, a pair is reported enforced only when both planes could be edited, and the result does
// not depend on the thread count.
namespace xsect {
namespace {

CuttingPlane plane(const Plane& pl, std::vector<Section> s, int slice) {
  CuttingPlane cp;
  cp.slice = slice;
  cp.plane = pl;
  cp.sections = std::move(s);
  cp.extent = {Vec2(-50, -50), Vec2(50, 50)};
  return cp;
}
Section rect(double u0, double u1, double v0, double v1) {
  return Section{Ring{{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}}, {}, 1};
}

TEST(Conformity, AnEndpointMoveLeavesOtherLinesCrossingsInPlace) {
  // P: z = 0. Its line with Q1 (y = 0) needs its left endpoint moved; the contour crosses the
  // line with Q2 (y = 1.06) just beside the move, and P agrees with Q2 there already.
  const Section p{Ring{{3, -1}, {3, 2}, {0, 2}, {0, 1.065}, {0, 0.985}, {0, -1}}, {}, 1};
  const std::vector<CuttingPlane> planes{plane(axisPlane(2, 0), {p}, 0),
                                         plane(axisPlane(1, 0), {rect(-1, 1, -0.25, 3)}, 1),
                                         plane(axisPlane(1, 1.06), {rect(-1, 1, 0, 3)}, 2)};
  const auto found = planePairTraces(planes, 5.0);
  ASSERT_EQ(found.pairs.size(), 2u);
  ConformityParams params;
  params.max_rounds = 1;
  const auto e = enforceConformity(planes, found.pairs, params);
  EXPECT_EQ(e.bumps, 1);
  for (const auto& q : retrace(found.pairs, e.planes)) EXPECT_LE(q.disagreement.symmetric_difference_mm, 1e-6);
}

TEST(Conformity, AnEditKeepsOffParallelLines) {
  // Q1 (x = 0) has a gap P lacks; Q2 (x = 0.5) agrees with P. Cutting the gap out of P along
  // x = 0 must not cut P along x = 0.5.
  const std::vector<CuttingPlane> planes{plane(axisPlane(2, 0), {rect(-10, 10, -10, 10)}, 0),
                                         plane(axisPlane(0, 0), {rect(-10, -1, -1, 1), rect(1, 10, -1, 1)}, 1),
                                         plane(axisPlane(0, 0.5), {rect(-10, 10, -1, 1)}, 2)};
  const auto found = planePairTraces(planes, 5.0);
  ASSERT_EQ(found.pairs.size(), 2u);
  for (const ConsensusMode mode : {ConsensusMode::intersection, ConsensusMode::average}) {
    ConformityParams params;
    params.mode = mode;
    params.max_rounds = 1;
    const auto e = enforceConformity(planes, found.pairs, params);
    for (const auto& q : retrace(found.pairs, e.planes)) EXPECT_LE(q.disagreement.symmetric_difference_mm, 1e-6);
  }
}

TEST(Conformity, AnEditKeepsOffLinesWithoutSections) {
  // Q2 (y = 4.5) crosses P where neither has a section; extending P along x = 0 to y = 6 must
  // not give P a trace on y = 4.5.
  const std::vector<CuttingPlane> planes{plane(axisPlane(2, 0), {disk({0, 0}, 3)}, 0),
                                         plane(axisPlane(0, 0), {rect(-3, 6, -1, 1)}, 1),
                                         plane(axisPlane(1, 4.5), {}, 2)};
  const auto found = planePairTraces(planes, 5.0);
  ASSERT_EQ(found.pairs.size(), 2u);       // P-Q1, and Q1-Q2 (Q1 has a section on it)
  ASSERT_EQ(found.unmeasured.size(), 1u);  // P-Q2
  const auto e = enforceConformity(planes, found.pairs, {}, found.unmeasured);
  EXPECT_TRUE(e.corrections[0].agrees);
  for (const auto& q : planePairTraces(e.planes, 5.0).pairs) EXPECT_LE(q.disagreement.symmetric_difference_mm, 1e-6) << q.a << "-" << q.b;
}

TEST(Conformity, APlaneThatCannotBeEditedLeavesItsPairsAlone) {
  const Section bow{Ring{{-5, -5}, {5, -5}, {5, 5}, {-5, 5}, {-4, -6}}, {}, 1};  // not simple
  const std::vector<CuttingPlane> planes{plane(axisPlane(2, 0), {bow}, 0), plane(axisPlane(0, 0), {rect(-4, 5, -1, 1)}, 1)};
  const auto found = planePairTraces(planes, 5.0);
  ASSERT_EQ(found.pairs.size(), 1u);
  const auto e = enforceConformity(planes, found.pairs, averaging());
  EXPECT_FALSE(e.corrections[0].applied);
  EXPECT_TRUE(e.corrections[0].not_editable);
  EXPECT_FALSE(e.corrections[0].agrees);
  EXPECT_EQ(e.planes_not_editable, std::vector<int>{0});
  EXPECT_EQ(e.planes_edited, 0) << "the partner is not edited alone";
}

TEST(Conformity, AnEndpointWhereObservationStopsIsNotMoved) {
  // Q is observed for y >= 0 only: P's trace end at y = -10 lies outside the common region; its
  // end at y = 10 moves to 9.5 by a bump.
  std::vector<CuttingPlane> planes{plane(axisPlane(2, 0), {Section{circle({0, 0}, 10, 256), {}, 1}}, 0),
                                   plane(axisPlane(0, 0), {Section{circle({5.25, 0}, 4.25, 256), {}, 1}}, 1)};
  planes[1].extent = {Vec2(0, -50), Vec2(50, 50)};
  const auto found = planePairTraces(planes, 5.0);
  ASSERT_EQ(found.pairs.size(), 1u);
  ConformityParams params;
  params.mode = ConsensusMode::intersection;
  const auto e = enforceConformity(planes, found.pairs, params);
  EXPECT_GE(e.bumps, 1);
  EXPECT_TRUE(e.corrections[0].agrees);
  EXPECT_EQ(e.planes[0].sections.size(), 1u);
}

TEST(Conformity, EnforcementIsTheSameWhateverTheThreadCount) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 0.4);
  std::vector<CuttingPlane> planes;
  for (int axis = 0; axis < 3; ++axis)
    for (int k = 0; k < 3; ++k)
      planes.push_back(plane(axisPlane(axis, 3.0 * (k - 1) + n(rng)),
                             {annulus({n(rng), n(rng)}, 10 + n(rng), 3 + std::abs(n(rng)), 97)}, axis * 3 + k));
  ConformityParams params = averaging();
  params.max_correction_mm = 100;
  const auto run = [&](int threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    return enforceConformity(planes, planePairTraces(planes, 5.0).pairs, params);
  };
  const auto e1 = run(1), e2 = run(2), e8 = run(8);
  for (std::size_t i = 0; i < planes.size(); ++i) {
    ASSERT_EQ(e1.planes[i].sections.size(), e8.planes[i].sections.size());
    ASSERT_EQ(e1.planes[i].sections.size(), e2.planes[i].sections.size());
    for (std::size_t s = 0; s < e1.planes[i].sections.size(); ++s) {
      EXPECT_EQ(e1.planes[i].sections[s].outer, e8.planes[i].sections[s].outer);
      EXPECT_EQ(e1.planes[i].sections[s].holes, e2.planes[i].sections[s].holes);
    }
  }
  const auto found = planePairTraces(planes, 5.0);
  const auto after = retrace(found.pairs, e1.planes);
  for (std::size_t k = 0; k < after.size(); ++k)
    EXPECT_LE(after[k].disagreement.symmetric_difference_mm, 1e-6) << after[k].a << "-" << after[k].b << " applied " << e1.corrections[k].applied << " over " << e1.corrections[k].over_max << " ne " << e1.corrections[k].not_editable << " before " << found.pairs[k].disagreement.symmetric_difference_mm << " rounds " << e1.rounds;
}

}  // namespace
}  // namespace xsect

// Issue 17: without enforcement the unmeasured pairs are only counted, never traced; the measured
// pairs and every count are those of the full search.
namespace xsect {
TEST(Conformity, CountingUnmeasuredPairsChangesNoMeasuredPair) {
  std::mt19937_64 rng(8);
  std::vector<CuttingPlane> planes = test::randomShellPlanes(30, rng, Vec3(0.1, -0.2, 0.3), 5.0, 6.0, 3.0);
  for (CuttingPlane& p : planes) p.observed_everywhere = true;
  for (const double minAngle : {5.0, 40.0, 70.0}) {
    const PlanePairSearch full = planePairTraces(planes, minAngle, true);
    const PlanePairSearch counted = planePairTraces(planes, minAngle, false);
    EXPECT_GT(full.pairs_near_parallel, 0) << minAngle;
    EXPECT_GT(full.pairs.size(), 0u) << minAngle;
    EXPECT_EQ(counted.pairs_near_parallel, full.pairs_near_parallel);
    EXPECT_EQ(counted.pairs_without_sections, full.pairs_without_sections);
    ASSERT_EQ(counted.pairs.size(), full.pairs.size());
    for (std::size_t k = 0; k < full.pairs.size(); ++k) {
      EXPECT_EQ(counted.pairs[k].a, full.pairs[k].a);
      EXPECT_EQ(counted.pairs[k].b, full.pairs[k].b);
      EXPECT_EQ(counted.pairs[k].disagreement.symmetric_difference_mm, full.pairs[k].disagreement.symmetric_difference_mm);
    }
    int unmeasuredNearParallel = 0;
    for (const PlanePairTraces& p : full.unmeasured) unmeasuredNearParallel += p.line.angle_deg < minAngle;
    EXPECT_EQ(unmeasuredNearParallel, full.pairs_near_parallel);
    EXPECT_EQ(int(counted.unmeasured.size()), full.pairs_without_sections);
  }
}
}  // namespace xsect
