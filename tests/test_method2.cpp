// Method 2 (thesis ch. 2, Def. 27-28) on a grid: equal to a brute-force evaluation of the
// definition, containing method 1 voxel by voxel (Theorem 18), unchanged by planes that pass beside
// the object where method 1 changes (Fig. 2.1-2.2), and conformal with the sections (thickening).
#include <gtest/gtest.h>

#include <random>

#include "geometry/reconstruction/nearest_plane_reconstruction.h"
#include "geometry/core/polygon.h"
#include "geometry/reconstruction/observed_section_voronoi.h"
#include "geometry/reconstruction/section_voronoi_reconstruction.h"
#include "geometry/scene/observed_piece.h"
#include "section_fixtures.h"

using namespace xsect;

namespace {

const Vec3 kCentre(0.3, -0.2, 0.1);

std::vector<SectionDistanceField> rasters(const std::vector<CuttingPlane>& planes, double step) {
  std::vector<SectionDistanceField> f;
  for (const auto& p : planes) f.push_back(sectionDistanceField(p.sections, step, 6 * step));
  return f;
}

GridSpec testGrid(double voxel, int n) {
  GridSpec g;
  g.voxel = voxel;
  g.origin = kCentre - Vec3::Constant(0.5 * voxel * (n - 1)) + Vec3(0.013, -0.007, 0.011);
  g.dims = {n, n + 1, n - 1};
  return g;
}

/// Convex polygon clipped by the half-plane a.p + c >= 0.
std::vector<Vec2> clip(const std::vector<Vec2>& poly, const Vec2& a, double c) {
  std::vector<Vec2> out;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2& A = poly[i];
    const Vec2& B = poly[(i + 1) % poly.size()];
    const double fa = a.dot(A) + c, fb = a.dot(B) + c;
    if (fa >= 0) out.push_back(A);
    if ((fa >= 0) != (fb >= 0)) out.push_back(A + fa / (fa - fb) * (B - A));
  }
  return out;
}

/// Distance from p to a convex counter-clockwise polygon (0 inside).
double convexDistance(const std::vector<Vec2>& poly, const Vec2& p) {
  bool inside = true;
  double best = 1e300;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2& A = poly[i];
    const Vec2& B = poly[(i + 1) % poly.size()];
    const Vec2 e = B - A;
    if (e.x() * (p - A).y() - e.y() * (p - A).x() < 0) inside = false;
    const double t = std::clamp((p - A).dot(e) / std::max(e.squaredNorm(), 1e-300), 0.0, 1.0);
    best = std::min(best, (A + t * e - p).norm());
  }
  return inside ? 0.0 : best;
}

struct Brute {
  bool inside = false;
  double Hin = 0, D = 0;
  double margin = 0;  // distance of x's data to a decision threshold (ties, contours, traces)
};

/// Def. 27-28 by brute force, for convex sections: for every plane P, the part of its section
/// that x sees (the section clipped by the half-spaces of all other planes that contain x), its
/// distance to x; x is in R' when the nearest of them is reached by an orthogonal projection.
Brute bruteForce(const Vec3& x, const std::vector<CuttingPlane>& planes) {
  struct PerPlane {
    double dist, height, near;  // distance to the visible part; |h| if in-section; tie margin
  };
  std::vector<PerPlane> per;
  double D = 1e300, Hin = 1e300;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const Plane& P = planes[i].plane;
    if (planes[i].sections.empty()) continue;
    const double h = P.signedDistance(x);
    const Vec2 p = P.toPlane(x);
    std::vector<Vec2> poly = planes[i].sections[0].outer;
    double near = ringDistance(planes[i].sections[0].outer, p);  // contour through p
    for (std::size_t j = 0; j < planes.size() && !poly.empty(); ++j) {
      if (j == i) continue;
      const Plane& Q = planes[j].plane;
      const double sg = Q.signedDistance(x) > 0 ? 1 : -1;
      const Vec2 a(sg * Q.normal.dot(P.u), sg * Q.normal.dot(P.v));
      const double c = sg * Q.signedDistance(P.origin);
      if (a.norm() < 1e-12) {
        if (c < 0) poly.clear();
        continue;
      }
      poly = clip(poly, a, c);
      if (std::abs(Q.signedDistance(x)) < std::abs(h) + 0.01)  // a trace that may hide p
        near = std::min(near, std::abs(a.dot(p) + c) / a.norm());
    }
    if (poly.size() < 3) continue;
    const double d = convexDistance(poly, p);
    per.push_back({std::hypot(h, d), d == 0 ? std::abs(h) : 1e300, near});
    D = std::min(D, std::hypot(h, d));
    if (d == 0) Hin = std::min(Hin, std::abs(h));
  }
  Brute b;
  b.inside = Hin < 1e299 && Hin <= D;
  b.Hin = Hin;
  b.D = D;
  // Gap between the winner and the nearest competitor of the other kind, and ties within the
  // planes that compete (contours and traces through their projections).
  b.margin = b.inside || D > 1e299 ? 1e300 : std::abs(Hin - D);
  for (const PerPlane& q : per) {
    if (b.inside && q.height != Hin) b.margin = std::min(b.margin, q.dist - Hin);
    if (q.dist <= std::min(D, Hin) + 0.05) b.margin = std::min(b.margin, q.near);
  }
  return b;
}

}  // namespace

TEST(Method2, EqualsTheBruteForceDefinition) {
  std::mt19937_64 rng(11);
  for (const int count : {3, 8, 14}) {
    SCOPED_TRACE(count);
    const auto planes = test::randomShellPlanes(count, rng, kCentre, 6.5, 6.0, 0.0, 64);
    const auto fields = rasters(planes, 0.02);
    const GridSpec grid = testGrid(0.4, 36);
    const SectionVoronoiField f = sectionVoronoiReconstruction(planes, fields, grid, {});
    std::int64_t inside = 0, checked = 0, skipped = 0;
    for (int k = 0; k < grid.dims[2]; ++k)
      for (int j = 0; j < grid.dims[1]; ++j)
        for (int i = 0; i < grid.dims[0]; ++i) {
          const Vec3 x = grid.centre(i, j, k);
          const Brute b = bruteForce(x, planes);
          const bool fast = f.value.at(i, j, k) < 0;
          if (b.margin < 1e-3) {  // within the rasters' tolerance of a decision threshold
            ++skipped;
            continue;
          }
          ++checked;
          inside += b.inside;
          ASSERT_EQ(fast, b.inside) << "voxel " << i << " " << j << " " << k << " margin " << b.margin << " Hin " << b.Hin << " D " << b.D
                                  << " value " << f.value.at(i, j, k) << " plane "
                                  << f.section_plane[std::size_t(grid.index(i, j, k))];
        }
    EXPECT_GT(inside, 1000);
    EXPECT_LT(skipped, checked / 20);
  }
}

// The point queries (the connectivity graph's, which clip one cell per ray and keep it in a memo
// while the ray stays in it) decide like the definition too, with and without the memo.
TEST(Method2, PointQueriesEqualTheBruteForceDefinitionWithAndWithoutTheCellMemo) {
  std::mt19937_64 rng(29);
  for (const int count : {5, 12}) {
    SCOPED_TRACE(count);
    const auto planes = test::randomShellPlanes(count, rng, kCentre, 6.5, 6.0, 0.0, 64);
    const auto fields = rasters(planes, 0.02);
    SectionVoronoiParams params;
    params.slab_mm = 0.05;
    const SectionVoronoiPoints query(planes, fields, params);
    std::uniform_real_distribution<double> unit(-1, 1);
    std::int64_t inside = 0, checked = 0, reused = 0;
    for (int ray = 0; ray < 300; ++ray) {
      const Vec3 a = kCentre + 8.0 * Vec3(unit(rng), unit(rng), unit(rng));
      const Vec3 dir = Vec3(unit(rng), unit(rng), unit(rng)).normalized();
      SectionVoronoiPoints::CellMemo memo;
      for (int k = 0; k < 40; ++k) {
        const Vec3 x = a + 0.2 * k * dir;
        const SectionVoronoiPoints::Answer alone = query.at(x), along = query.at(x, &memo);
        ASSERT_EQ(alone.inside, along.inside) << "ray " << ray << " step " << k;
        ASSERT_EQ(alone.section_plane, along.section_plane);
        double nearest = 1e300;
        for (const auto& P : planes) nearest = std::min(nearest, std::abs(P.plane.signedDistance(x)));
        if (nearest < params.slab_mm) continue;  // the thickened planes are not the definition
        const Brute b = bruteForce(x, planes);
        if (b.margin < 1e-3) continue;
        ++checked;
        inside += b.inside;
        ASSERT_EQ(alone.inside, b.inside) << "ray " << ray << " step " << k << " Hin " << b.Hin << " D " << b.D;
      }
      reused += memo.reuses;
    }
    EXPECT_GT(inside, 100);
    EXPECT_GT(checked, 5000);
    EXPECT_GT(reused, 1000);  // queries that found their point in the memo's cell
  }
}

TEST(Method2, ContainsMethod1VoxelByVoxel) {  // Theorem 18: R ⊆ R'
  std::mt19937_64 rng(5);
  for (const int count : {2, 9, 40, 120}) {
    for (const double slab : {0.0, 0.35}) {
      SCOPED_TRACE(std::to_string(count) + " planes, slab " + std::to_string(slab));
      const auto planes = test::randomShellPlanes(count, rng, kCentre, 7.0, 6.0, 3.0, 96);  // shells: non-convex sections
      const auto fields = rasters(planes, 0.1);
      const GridSpec grid = testGrid(0.4, 40);
      const NearestPlaneField r = nearestPlaneReconstruction(planes, fields, grid);
      SectionVoronoiParams vp;
      vp.slab_mm = slab;
      const SectionVoronoiField r2 = sectionVoronoiReconstruction(planes, fields, grid, vp);
      std::int64_t inR = 0, inR2 = 0;
      for (std::size_t q = 0; q < r.value.values.size(); ++q) {
        const bool a = r.value.values[q] < 0, b = r2.value.values[q] < 0;
        inR += a;
        inR2 += b;
        ASSERT_TRUE(!a || b) << "voxel " << q << " in R but not in R'";
        if (b) {
          ASSERT_GE(r2.section_plane[q], 0);
          ASSERT_GE(r2.lift_height[q], 0.f);
        }
      }
      EXPECT_GT(inR, 0);
      EXPECT_GE(inR2, inR);
    }
  }
}

namespace {

struct ObservedLiftCounts {
  std::int64_t kept = 0, dropped = 0, added = 0;
  std::int64_t kept_by_observed_ball = 0, kept_alone = 0;  ///< which condition kept them (the first that holds)
};

/// Compares R'_Ω on `planes` (their extents the pieces) with its definition voxel by voxel, and
/// with R' on whole pieces and on pieces that cover every ball; adds its lift counts to *counts.
/// `dropped_at`: a point whose voxel must be a dropped lift (R' \ R_Ω, not in R'_Ω), or none.
void expectObservedMethod2AsDefined(const std::vector<CuttingPlane>& planes, const GridSpec& grid,
                                    ObservedLiftCounts* counts, const Vec3* dropped_at = nullptr) {
  const auto fields = rasters(planes, 0.1);
  SectionVoronoiParams vp;
  vp.slab_mm = 0.35;
  const std::vector<ObservedPiece> pieces = observedPieces(planes, true);
  const SectionVoronoiField r2 = sectionVoronoiReconstruction(planes, fields, grid, vp);
  const NearestPlaneField r1 = nearestPlaneReconstruction(planes, fields, grid, {}, &pieces);
  std::vector<float> value(std::size_t(grid.count()), 0.f);
  const BlockGrid<float> numbering(grid, 0.f);
  ObservedSectionVoronoiStatistics st;
  forEachObservedSectionVoronoiBlock(planes, fields, pieces, grid, vp, [&](std::int64_t b, const SectionVoronoiBlock& v) {
    forEachVoxelOfBlock(grid, numbering.blockOrigin(b), [&](int i, int j, int k, int o) {
      value[std::size_t(grid.index(i, j, k))] = v.value[std::size_t(o)];
    });
  }, {}, &st);
  std::int64_t mismatches = 0;
  ObservedLiftCounts here;
  for (int k = 0; k < grid.dims[2]; ++k)
    for (int j = 0; j < grid.dims[1]; ++j)
      for (int i = 0; i < grid.dims[0]; ++i) {
        const std::size_t q = std::size_t(grid.index(i, j, k));
        const Vec3 x = grid.centre(i, j, k);
        const bool in1 = r1.value.values[q] < 0, in2 = r2.value.values[q] < 0;
        const int A = r2.section_plane[q];
        bool foot = in2 && A >= 0;
        if (foot) {  // x's projection on the lift's plane is observed
          const Vec2 c = planes[std::size_t(A)].plane.toPlane(x);
          double na, nb;
          foot = pieces[std::size_t(A)].distance(c.x(), c.y(), &na, &nb) == 0;
        }
        // Every plane within h observed over its disc of B(x, h): the rim at every 22.5° (a
        // rectangle's extremes among them).
        bool ball = foot;
        const double h = r2.lift_height[q];
        for (std::size_t p = 0; ball && p < planes.size(); ++p) {
          const double s = std::abs(planes[p].plane.signedDistance(x));
          if (s > h * (1 + 1e-9)) continue;
          const double r = std::sqrt(std::max(0.0, h * h - s * s));
          const Vec2 c = planes[p].plane.toPlane(x);
          for (int t = 0; t < 16 && ball; ++t) {
            const double a = t * M_PI / 8;
            double na, nb;
            ball = pieces[p].distance(c.x() + r * std::cos(a), c.y() + r * std::sin(a), &na, &nb) == 0;
          }
        }
        // ... or no section point but the lift's foot within B(x, h): distances to the polygons
        // (a section within 1e-9 mm of the ball is a tie either answer may take).
        bool alone = foot, tie = false;
        for (std::size_t p = 0; foot && !ball && p < planes.size(); ++p) {
          if (int(p) == A || planes[p].sections.empty()) continue;
          const double s = std::abs(planes[p].plane.signedDistance(x));
          if (s >= h) continue;
          const double r = std::sqrt(h * h - s * s);
          const double d = signedDistanceToSections(planes[p].sections, planes[p].plane.toPlane(x));
          if (d < r) alone = false;
          else if (d < r + 1e-9) tie = true;
        }
        const bool want = in1 || ball || alone;
        if (!(tie && want != (value[q] < 0))) mismatches += want != (value[q] < 0);
        here.kept += in2 && !in1 && value[q] < 0;
        here.dropped += in2 && !in1 && !(value[q] < 0);
        here.added += in1 && !in2;
        here.kept_by_observed_ball += in2 && !in1 && ball && value[q] < 0;
        here.kept_alone += in2 && !in1 && !ball && alone && value[q] < 0;
      }
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(st.lift_voxels_kept, here.kept);
  EXPECT_EQ(st.lift_voxels_dropped, here.dropped);
  EXPECT_EQ(st.pieces_voxels_added, here.added);
  counts->kept += here.kept;
  counts->dropped += here.dropped;
  counts->added += here.added;
  counts->kept_by_observed_ball += here.kept_by_observed_ball;
  counts->kept_alone += here.kept_alone;
  if (dropped_at) {
    const Vec3 f = (*dropped_at - grid.origin) / grid.voxel;
    const std::size_t q = std::size_t(grid.index(int(std::lround(f.x())), int(std::lround(f.y())), int(std::lround(f.z()))));
    EXPECT_TRUE(r2.value.values[q] < 0 && !(r1.value.values[q] < 0) && !(value[q] < 0))
        << "R' " << r2.value.values[q] << ", R_Ω " << r1.value.values[q] << ", R'_Ω " << value[q];
  }
  // Whole pieces: R' itself, value for value; pieces that cover every ball (rectangles 100 mm
  // across, the general path): R' voxel for voxel.
  const std::vector<ObservedPiece> whole = observedPieces(planes, false);
  std::vector<CuttingPlane> covering = planes;
  for (CuttingPlane& p : covering)
    if (!p.is_virtual) p.extent = {Vec2(-50, -50), Vec2(50, 50)};
  const std::vector<ObservedPiece> large = observedPieces(covering, true);
  ASSERT_FALSE(large[0].whole);
  std::int64_t differ = 0, differLarge = 0;
  forEachObservedSectionVoronoiBlock(planes, fields, whole, grid, vp, [&](std::int64_t b, const SectionVoronoiBlock& v) {
    forEachVoxelOfBlock(grid, numbering.blockOrigin(b), [&](int i, int j, int k, int o) {
      differ += v.value[std::size_t(o)] != r2.value.values[std::size_t(grid.index(i, j, k))];
    });
  });
  forEachObservedSectionVoronoiBlock(planes, fields, large, grid, vp, [&](std::int64_t b, const SectionVoronoiBlock& v) {
    forEachVoxelOfBlock(grid, numbering.blockOrigin(b), [&](int i, int j, int k, int o) {
      differLarge += (v.value[std::size_t(o)] < 0) != (r2.value.values[std::size_t(grid.index(i, j, k))] < 0);
    });
  });
  EXPECT_EQ(differ, 0);
  EXPECT_EQ(differLarge, 0);
}

}  // namespace

// Method 2 on observed pieces (docs/methods.md, "Observed pieces"): every voxel as the definition says,
// R'_Ω = R_Ω ∪ {x ∈ R' : the lift's foot observed, and within B(x, h(x)) every plane observed or
// no section point but the foot}, with R' and R_Ω evaluated on their own. Shells cut by planes cut
// down to random image rectangles keep lifts by either condition, drop lifts and add method 1's
// voxels; a lift towards a section behind a plane observed only in part is dropped. With whole
// pieces, or pieces that cover every ball, it is method 2 itself.
TEST(Method2, OnObservedPiecesEqualsItsDefinition) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> size(1.0, 9.0);
  ObservedLiftCounts counts;
  for (const int count : {9, 40, 120}) {
    SCOPED_TRACE(std::to_string(count) + " planes");
    auto planes = test::randomShellPlanes(count, rng, kCentre, 7.0, 6.0, 3.0, 96);
    for (CuttingPlane& p : planes) {
      p.pixel_mm = 0.1;
      p.extent = {Vec2(-size(rng), -size(rng)), Vec2(size(rng), size(rng))};
    }
    expectObservedMethod2AsDefined(planes, testGrid(0.4, 40), &counts);
  }
  EXPECT_GT(counts.kept_by_observed_ball, 0) << "the test must keep lifts whose ball is observed";
  EXPECT_GT(counts.kept_alone, 0) << "the test must keep lifts whose ball holds no other section";
  EXPECT_GT(counts.dropped, 0) << "the test must drop lifts";
  EXPECT_GT(counts.added, 0) << "the test must add method 1's voxels";
  // A disc on z = 0; above it a plane z = 2 without section observed only for x <= 0; beyond it a
  // small disc on z = 2.6 at x = 2.5. At (1.5, 0, 1.5) method 2 on whole planes lifts the lower
  // disc (the plane z = 2 hides the small disc); through the unobserved part of z = 2 the small
  // disc is nearer than the lift's foot, not by a projection: the lift is dropped, and method 1 on
  // the pieces (nearest piece z = 2.6, outside its disc) says outside.
  {
    SCOPED_TRACE("a section behind a plane observed in part");
    std::vector<CuttingPlane> planes;
    const auto add = [&](int axis, double offset, std::vector<Section> sections, PlaneRect extent, bool closing) {
      planes.push_back(test::observedPlane(test::axisPlane(axis, offset), std::move(sections), extent, 0.1,
                                           int(planes.size()), closing));
    };
    Section big, small;
    big.outer = test::circle(Vec2(0, 0), 3.0, 128);
    small.outer = test::circle(Vec2(2.5, 0), 0.5, 64);
    const PlaneRect all{Vec2(-10, -10), Vec2(10, 10)};
    add(2, 0.0, {big}, all, false);
    add(2, 2.0, {}, PlaneRect{Vec2(-10, -10), Vec2(0, 10)}, false);
    add(2, 2.6, {small}, all, false);
    for (int axis = 0; axis < 2; ++axis) {
      add(axis, -5.0, {}, all, true);
      add(axis, 5.0, {}, all, true);
    }
    add(2, -2.0, {}, all, true);
    add(2, 5.0, {}, all, true);
    GridSpec grid;
    grid.voxel = 0.1;
    grid.origin = Vec3(-4.0, -4.0, -1.5);
    grid.dims = {81, 81, 61};
    const Vec3 x(1.5, 0.0, 1.5);
    const std::int64_t before = counts.dropped;
    expectObservedMethod2AsDefined(planes, grid, &counts, &x);
    EXPECT_GT(counts.dropped, before) << "the test must drop lifts";
  }
}

namespace {

/// Thesis Fig. 2.1-2.2 in 3D: a slanted thin tube cut by two parallel planes (disks whose
/// projections overlap), optionally with two more planes that pass beside it.
std::vector<CuttingPlane> tubeScene(bool extraPlanes) {
  std::vector<CuttingPlane> planes;
  const auto add = [&](const Plane& p, std::vector<Section> s) {
    CuttingPlane cp;
    cp.slice = int(planes.size());
    cp.plane = p;
    cp.sections = std::move(s);
    planes.push_back(cp);
  };
  Section a, b;
  a.outer = test::circle(Vec2(0, 0), 1.0, 128);
  b.outer = test::circle(Vec2(1.5, 0), 1.0, 128);
  add(test::axisPlane(2, 0.0), {a});
  add(test::axisPlane(2, 6.0), {b});
  // Virtual-like empty planes closing the scene around the tube.
  for (int axis = 0; axis < 2; ++axis) {
    add(test::axisPlane(axis, -8.0), {});
    add(test::axisPlane(axis, 9.0), {});
  }
  add(test::axisPlane(2, -3.0), {});
  add(test::axisPlane(2, 9.0), {});
  if (extraPlanes) {  // beside the tube (which spans x in [-1, 2.5]), not touching it
    Plane p = test::axisPlane(0, -1.6);
    add(p, {});
    p = test::axisPlane(0, 3.1);
    add(p, {});
  }
  return planes;
}

}  // namespace

TEST(Method2, PlanesBesideTheObjectChangeMethod1NotMethod2) {  // thesis Fig. 2.1-2.2
  GridSpec grid;
  grid.voxel = 0.1;
  grid.origin = Vec3(-2.95, -1.95, -0.95);
  grid.dims = {80, 40, 80};
  std::vector<std::uint8_t> r[2], r2[2];
  for (int extra = 0; extra < 2; ++extra) {
    const auto planes = tubeScene(extra);
    const auto fields = rasters(planes, 0.02);
    const auto m1 = nearestPlaneReconstruction(planes, fields, grid);
    SectionVoronoiParams vp;
    vp.slab_mm = 0.09;
    const auto m2 = sectionVoronoiReconstruction(planes, fields, grid, vp);
    for (std::size_t q = 0; q < m1.value.values.size(); ++q) {
      r[extra].push_back(m1.value.values[q] < 0);
      r2[extra].push_back(m2.value.values[q] < 0);
    }
  }
  std::int64_t changed1 = 0, changed2 = 0, in2 = 0;
  for (std::size_t q = 0; q < r[0].size(); ++q) {
    changed1 += r[0][q] != r[1][q];
    changed2 += r2[0][q] != r2[1][q];
    in2 += r2[0][q];
  }
  EXPECT_GT(changed1, 500) << "method 1 should depend on the planes beside the tube";
  EXPECT_EQ(changed2, 0) << "method 2 should not";
  EXPECT_GT(in2, 10000);
}

TEST(Method2, ThickenedPlanesKeepTheSolidOnThePlanesEqualToTheSections) {
  // Near a plane (within the slab) R' is decided by that plane's sections alone: a lift reaching
  // a face of its cell outside the sections (Fig. 2.6) stops short of it.
  const auto planes = tubeScene(false);
  const auto fields = rasters(planes, 0.02);
  GridSpec grid;
  grid.voxel = 0.1;
  grid.origin = Vec3(-2.95, -1.95, -0.95);
  grid.dims = {80, 40, 100};
  SectionVoronoiParams vp;
  vp.slab_mm = 0.0866;
  const auto m2 = sectionVoronoiReconstruction(planes, fields, grid, vp);
  std::int64_t nearPlane = 0;
  for (int k = 0; k < grid.dims[2]; ++k)
    for (int j = 0; j < grid.dims[1]; ++j)
      for (int i = 0; i < grid.dims[0]; ++i) {
        const Vec3 x = grid.centre(i, j, k);
        for (const auto& cp : planes) {
          if (std::abs(cp.plane.signedDistance(x)) >= vp.slab_mm) continue;
          ++nearPlane;
          const bool inSection = !cp.sections.empty() && sectionContains(cp.sections[0], cp.plane.toPlane(x));
          const double margin = cp.sections.empty() ? 1.0 : ringDistance(cp.sections[0].outer, cp.plane.toPlane(x));
          if (margin > 0.01) ASSERT_EQ(m2.value.at(i, j, k) < 0, inSection) << i << " " << j << " " << k;
        }
      }
  EXPECT_GT(nearPlane, 1000);
  // Above the top disk its cell is closed by the empty plane z = 9: the disk's lift reaches that
  // face outside any section (Fig. 2.6) without thickening, and stops short of it with it.
  vp.slab_mm = 0;
  const auto bare = sectionVoronoiReconstruction(planes, fields, grid, vp);
  int top = 0, bareTop = 0;
  for (int j = 0; j < grid.dims[1]; ++j)
    for (int i = 0; i < grid.dims[0]; ++i) {
      top += m2.value.at(i, j, grid.dims[2] - 1) < 0;
      bareTop += bare.value.at(i, j, grid.dims[2] - 1) < 0;
    }
  EXPECT_EQ(top, 0);
  EXPECT_GT(bareTop, 100);
}
