// Shepard's interpolant (thesis ch. 1 §1.1): the grid evaluation equals the O(k²) definition, the
// far-field f_i stays within its stated error of the exact polygon distance, f equals f_i on the
// planes (Property 3: the zero set passes through the contours), and as p grows the solid
// approaches method 1's (the thesis' "sufficiently large n" remark), p = inf being method 1. On
// observed pieces (issue 20) the grid equals the pieces' definition, and is the whole planes' where
// the pieces hold every projection.
#include <gtest/gtest.h>

#include <functional>
#include <random>

#include "geometry/scene/end_planes.h"
#include "geometry/reconstruction/nearest_plane_reconstruction.h"
#include "geometry/smoothing/plane_distance_function.h"
#include "geometry/core/polygon.h"
#include "geometry/smoothing/shepard_interpolant.h"
#include "section_fixtures.h"

using namespace xsect;

namespace {

const Vec3 kCentre(0.3, -0.2, 0.1);

/// Planes (random shell sections, plus the six end planes), their rasters and f_i on `grid`.
struct Scene {
  std::vector<CuttingPlane> planes;
  std::vector<SectionDistanceField> near;
  std::vector<PlaneDistanceFunction> f;
  GridSpec grid;
  std::vector<double> factor;  ///< the end planes' weight factors (endPlaneWeightFactors)
  ShepardData data() const { return {&planes, &near, &f, &factor}; }
};

Scene scene(int count, unsigned seed, double voxel, int n, double Ri) {
  Scene s;
  std::mt19937_64 rng(seed);
  s.planes = test::randomShellPlanes(count, rng, kCentre, 2.0, 3.0, Ri, 64);
  const auto ends = endPlanes(kCentre - Vec3::Constant(3.0), kCentre + Vec3::Constant(3.0), 0.8);
  s.planes.insert(s.planes.end(), ends.begin(), ends.end());
  s.factor = endPlaneWeightFactors(s.planes, std::size_t(count));
  s.grid.voxel = voxel;
  s.grid.origin = kCentre - Vec3::Constant(0.5 * voxel * (n - 1)) + Vec3(0.013, -0.007, 0.011);
  s.grid.dims = {n, n + 1, n - 1};
  for (const auto& p : s.planes) {
    s.near.push_back(sectionDistanceField(p.sections, 0.5 * voxel, 3 * voxel));
    s.f.push_back(planeDistanceFunction(s.near.back(), p.plane, s.grid, p.sections.empty() ? 0.8 : 3.0));
  }
  return s;
}

/// Distance of x to the nearest visibility tie (a projection x_i within reach of a plane that may
/// hide it): where the visible set changes, f jumps, so the definition and the grid may differ.
double tieMargin(const std::vector<CuttingPlane>& planes, const Vec3& x) {
  double m = 1e300;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const double si = planes[i].plane.signedDistance(x);
    const Vec3 xi = x - si * planes[i].plane.normal;
    for (std::size_t q = 0; q < planes.size(); ++q)
      if (q != i && std::abs(planes[q].plane.signedDistance(x)) < std::abs(si))
        m = std::min(m, std::abs(planes[q].plane.signedDistance(xi)));
  }
  return m;
}

/// The grid evaluation against the definition at every voxel centre not within 1e-6 of a
/// visibility tie (`margin`).
struct Comparison {
  int compared = 0, skipped = 0, max_visible = 0, differing = 0;  ///< differing: by more than 1e-5
  double worst = 0;
};
Comparison compareWithDefinition(const ShepardData& data, const GridSpec& grid, double p, const ShepardField& fast,
                                 const std::function<double(const Vec3&)>& margin) {
  Comparison c;
  const auto& D = grid.dims;
  for (int k = 0; k < D[2]; ++k)
    for (int j = 0; j < D[1]; ++j)
      for (int i = 0; i < D[0]; ++i) {
        const Vec3 x = grid.centre(i, j, k);
        if (margin(x) < 1e-6) {
          ++c.skipped;
          continue;
        }
        int visible = 0;
        const double d = std::abs(shepardValue(data, x, p, &visible) - double(fast.value.at(i, j, k)));
        c.max_visible = std::max(c.max_visible, visible);
        c.worst = std::max(c.worst, d);
        c.differing += d > 1e-5;
        ++c.compared;
      }
  return c;
}

}  // namespace

TEST(Shepard, GridEvaluationEqualsTheDefinition) {
  for (const int count : {3, 8, 14, 30})
    for (const double p : {1.0, 2.0, 8.0, std::numeric_limits<double>::infinity()}) {
      const Scene s = scene(count, 100 + count, 0.25, 26, 1.2);
      const ShepardField fast = shepardInterpolant(s.data(), s.grid, p);
      const Comparison c =
          compareWithDefinition(s.data(), s.grid, p, fast, [&](const Vec3& x) { return tieMargin(s.planes, x); });
      EXPECT_LE(c.worst, 1e-5) << count << " planes, p = " << p;
      EXPECT_LT(c.skipped, c.compared / 1000 + 1) << count << " planes";
      EXPECT_EQ(fast.max_visible_planes, c.max_visible) << count << " planes, p = " << p;
    }
}

TEST(Shepard, DistanceFunctionWithinItsErrorBoundOfTheExactPolygonDistance) {
  const Scene s = scene(12, 7, 0.2, 30, 1.5);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-4.0, 4.0);
  for (std::size_t i = 0; i < s.planes.size(); ++i) {
    if (s.planes[i].sections.empty()) continue;
    const double bound = farErrorBound(s.f[i]);
    double worstNear = 0, worstFar = 0;
    for (int n = 0; n < 4000; ++n) {
      const Vec2 ab(u(rng), u(rng));
      const Vec3 x = s.planes[i].plane.toWorld(ab);
      bool inGrid = true;
      for (int a = 0; a < 3; ++a)
        inGrid = inGrid && x[a] >= s.grid.origin[a] &&
                 x[a] <= s.grid.origin[a] + s.grid.voxel * (s.grid.dims[a] - 1);
      if (!inGrid) continue;
      const double exact = std::min(signedDistanceToSections(s.planes[i].sections, ab), double(s.f[i].cap));
      const double got = planeDistanceValue(s.near[i], s.f[i], ab.x(), ab.y());
      const double err = std::abs(got - exact);
      (std::abs(exact) < 0.5 * s.near[i].band ? worstNear : worstFar) =
          std::max(std::abs(exact) < 0.5 * s.near[i].band ? worstNear : worstFar, err);
      ASSERT_LE(err, bound) << "plane " << i << " at (" << ab.transpose() << "), exact " << exact;
      if (std::abs(exact) > 0.25 * bound)  // the sign is right wherever the error cannot flip it
        ASSERT_EQ(got < 0, exact < 0) << "plane " << i << " at (" << ab.transpose() << ")";
    }
    // Near the contours the band raster's bilinear error is far below the bound.
    EXPECT_LT(worstNear, 0.25 * bound) << "plane " << i;
  }
}

TEST(Shepard, EqualsEachPlanesFunctionOnItsPlaneSoTheZeroSetPassesThroughTheContours) {
  const Scene s = scene(10, 21, 0.25, 20, 1.0);
  for (const double p : {1.0, 2.0, 32.0}) {
    double worst = 0;
    int samples = 0;
    for (std::size_t i = 0; i < s.planes.size(); ++i)
      for (const Section& sec : s.planes[i].sections)
        for (const Vec2& a : sec.outer) {
          // A point on the contour: f_i = 0 there, and f = f_i on P_i (Property 3), unless it
          // also lies on another plane (then f is the mean of their f_j, all 0 on a conforming
          // intersection line: these shell sections conform).
          const double v = shepardValue(s.data(), s.planes[i].plane.toWorld(a), p);
          worst = std::max(worst, std::abs(v));
          ++samples;
        }
    EXPECT_GT(samples, 100);
    // f_i at a contour vertex: the band raster's bilinear error only (exact at its nodes).
    EXPECT_LE(worst, 0.25 * 0.125) << "p = " << p;
  }
}

TEST(Shepard, ApproachesMethod1AsTheExponentGrows) {
  // The thesis (§1.1): for a sufficiently large n, R_f is close to R. p = inf is method 1 exactly.
  const Scene s = scene(24, 5, 0.2, 40, 1.4);
  const NearestPlaneField m1 = nearestPlaneReconstruction(s.planes, s.near, s.grid);
  const auto iou = [&](const ScalarField& f) {
    std::int64_t both = 0, either = 0;
    for (std::size_t q = 0; q < f.values.size(); ++q) {
      const bool a = f.values[q] < 0, b = m1.value.values[q] < 0;
      both += a && b;
      either += a || b;
    }
    return double(both) / double(either);
  };
  double previous = 0;
  for (const double p : {2.0, 8.0, 32.0}) {
    const double v = iou(shepardInterpolant(s.data(), s.grid, p).value);
    EXPECT_GT(v, previous) << "p = " << p;
    previous = v;
    if (p == 32.0) EXPECT_GE(v, 0.98);
  }
  const ShepardField inf = shepardInterpolant(s.data(), s.grid, std::numeric_limits<double>::infinity());
  std::int64_t differ = 0;
  for (std::size_t q = 0; q < inf.value.values.size(); ++q)
    differ += (inf.value.values[q] < 0) != (m1.value.values[q] < 0);
  EXPECT_EQ(differ, 0);
}

TEST(Shepard, TwoParallelPlanesWithTheIdentityWeightInterpolateLinearly) {
  // The thesis (§1.1): "in the case where we have two parallel cutting planes and h_i = |x - x_i|
  // (g the identity), we obtain the standard linear interpolation between the distance functions
  // to the contours". Discs of radius 3 (z = 0) and 2 (z = 2): the linear interpolation of their
  // signed distances, r - 3 + z/2, vanishes on the frustum r = 3 - z/2. The scene is closed by the
  // six end planes; the four beside the stack must not pull the frustum in (with their full
  // weight, f on the frustum is off by up to 0.4 mm and 1372 voxels change sides).
  Scene s;
  for (const auto& [z, r] : {std::pair{0.0, 3.0}, std::pair{2.0, 2.0}}) {
    CuttingPlane c;
    c.plane = test::axisPlane(2, z);
    c.sections.push_back(Section{test::circle(Vec2::Zero(), r, 720), {}});
    s.planes.push_back(c);
  }
  const auto ends = endPlanes(Vec3(-3, -3, 0), Vec3(3, 3, 2), 1.0);
  s.planes.insert(s.planes.end(), ends.begin(), ends.end());
  s.factor = endPlaneWeightFactors(s.planes, 2);
  for (std::size_t e = 2; e < s.planes.size(); ++e)
    EXPECT_EQ(s.factor[e], std::abs(s.planes[e].plane.normal.z()) > 0.5 ? 1.0 : 0.0) << s.planes[e].name;
  s.grid.voxel = 0.2;
  s.grid.origin = Vec3(-4.1, -4.1, -1.1);
  s.grid.dims = {42, 42, 22};
  // A band of 1.5 mm holds both discs' distances on the whole frustum (|f_i| <= 1 there), so f_i
  // is the band raster's (exact at its nodes) and not the coarser far-field one.
  for (const auto& p : s.planes) {
    s.near.push_back(sectionDistanceField(p.sections, 0.5 * s.grid.voxel, 1.5));
    s.f.push_back(planeDistanceFunction(s.near.back(), p.plane, s.grid, p.sections.empty() ? 1.0 : 3.0));
  }
  double worst = 0;
  for (int k = 1; k < 20; ++k)
    for (int a = 0; a < 36; ++a) {
      const double z = 0.1 * k, r = 3 - z / 2, phi = 2 * M_PI * (a + 0.3) / 36;
      worst = std::max(worst, std::abs(shepardValue(s.data(), Vec3(r * std::cos(phi), r * std::sin(phi), z), 1.0)));
    }
  EXPECT_LE(worst, 2e-3);  // the band rasters' bilinear error at the contours
  // The grid evaluation has the frustum's inside and outside, and equals the definition.
  const ShepardField g = shepardInterpolant(s.data(), s.grid, 1.0);
  int wrong = 0, compared = 0;
  for (int k = 0; k < s.grid.dims[2]; ++k)
    for (int j = 0; j < s.grid.dims[1]; ++j)
      for (int i = 0; i < s.grid.dims[0]; ++i) {
        const Vec3 x = s.grid.centre(i, j, k);
        if (!(x.z() > 0 && x.z() < 2)) continue;
        const double off = std::hypot(x.x(), x.y()) - (3 - x.z() / 2);
        EXPECT_NEAR(g.value.at(i, j, k), shepardValue(s.data(), x, 1.0), 1e-5);
        if (std::abs(off) < 0.01) continue;
        ++compared;
        wrong += (g.value.at(i, j, k) < 0) != (off < 0);
      }
  EXPECT_GT(compared, 5000);
  EXPECT_EQ(wrong, 0);
}

TEST(Shepard, RejectsInvalidArguments) {
  const Scene s = scene(3, 1, 0.5, 6, 0.0);
  EXPECT_THROW(shepardInterpolant(s.data(), s.grid, 0.0), std::invalid_argument);
  EXPECT_THROW(shepardInterpolant(s.data(), s.grid, -2.0), std::invalid_argument);
  std::vector<PlaneDistanceFunction> few(s.f.begin(), s.f.begin() + 1);
  EXPECT_THROW(shepardInterpolant({&s.planes, &s.near, &few}, s.grid, 2.0), std::invalid_argument);
  const std::vector<double> shortFactors(2, 1.0), negative(s.planes.size(), -1.0);
  EXPECT_THROW(shepardInterpolant({&s.planes, &s.near, &s.f, &shortFactors}, s.grid, 2.0), std::invalid_argument);
  EXPECT_THROW(shepardInterpolant({&s.planes, &s.near, &s.f, &negative}, s.grid, 2.0), std::invalid_argument);
  EXPECT_THROW(planeDistanceFunction(s.near[0], s.planes[0].plane, s.grid, 0.0), std::invalid_argument);
}

namespace {

/// Distance of x to the nearest visibility tie on observed pieces: a plane q nearer than t_i whose
/// sign at x_i (the piece's nearest point) is nearly 0, or whose crossing of [x, x_i] lies within
/// reach of its rectangle's edge lines.
double pieceTieMargin(const std::vector<CuttingPlane>& planes, const std::vector<ObservedPiece>& pieces, const Vec3& x) {
  double m = 1e300;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const Plane& P = planes[i].plane;
    const Vec2 ab = P.toPlane(x);
    double na, nb;
    const double o = pieces[i].distance(ab.x(), ab.y(), &na, &nb), si = P.signedDistance(x);
    const Vec3 xi = P.toWorld(Vec2(na, nb));
    const double ti = std::sqrt(si * si + o * o);
    for (std::size_t q = 0; q < planes.size(); ++q) {
      const double sq = planes[q].plane.signedDistance(x), sqi = planes[q].plane.signedDistance(xi);
      if (q == i || !(std::abs(sq) < ti)) continue;
      m = std::min(m, std::abs(sqi));
      if (sq * sqi < 0 && !pieces[q].whole) {
        const Vec2 z = planes[q].plane.toPlane(x + (sq / (sq - sqi)) * (xi - x));
        const PlaneRect& r = pieces[q].rect;
        m = std::min({m, std::abs(z.x() - r.min.x()), std::abs(z.x() - r.max.x()), std::abs(z.y() - r.min.y()),
                      std::abs(z.y() - r.max.y())});
      }
    }
  }
  return m;
}

}  // namespace

// Shepard on observed pieces (shepard_interpolant.h): the block-culled grid equals the definition
// (x_i the piece's nearest point, visibility blocked only inside other pieces) on random planes cut
// down to random rectangles; with pieces that hold every projection it is the whole-plane grid.
TEST(Shepard, OnObservedPiecesTheGridEqualsTheDefinition) {
  std::mt19937_64 rng(77);
  for (const int count : {4, 9, 16})
    for (const double p : {1.0, 2.0, std::numeric_limits<double>::infinity()}) {
      Scene s = scene(count, 300 + count, 0.25, 22, 1.2);
      std::vector<ObservedPiece> pieces(s.planes.size());
      int partial = 0;
      for (std::size_t i = 0; i < std::size_t(count); ++i) {
        if (std::uniform_real_distribution<double>(0, 1)(rng) < 0.2) continue;  // some stay whole
        // A rectangle about a random point within 2 mm of the sections' centre, 1-4 mm a side.
        std::uniform_real_distribution<double> c(-2.0, 2.0), side(1.0, 4.0);
        const Vec2 centre = s.planes[i].plane.toPlane(kCentre) + Vec2(c(rng), c(rng));
        const Vec2 half(0.5 * side(rng), 0.5 * side(rng));
        pieces[i].whole = false;
        pieces[i].rect = PlaneRect{centre - half, centre + half};
        ++partial;
      }
      ShepardData data = s.data();
      data.pieces = &pieces;
      const ShepardField fast = shepardInterpolant(data, s.grid, p);
      const Comparison c =
          compareWithDefinition(data, s.grid, p, fast, [&](const Vec3& x) { return pieceTieMargin(s.planes, pieces, x); });
      EXPECT_GT(partial, 0);
      EXPECT_LE(c.worst, 1e-5) << count << " planes, p = " << p << ", " << c.differing << " voxels differ";
      EXPECT_LT(c.skipped, c.compared / 1000 + 1) << count << " planes";
      EXPECT_EQ(fast.max_visible_planes, c.max_visible) << count << " planes, p = " << p;
      // The pieces differ from whole planes somewhere on this grid.
      const ShepardField whole = shepardInterpolant(s.data(), s.grid, p);
      int differ = 0;
      for (std::size_t q = 0; q < whole.value.values.size(); ++q)
        differ += std::abs(whole.value.values[q] - fast.value.values[q]) > 1e-4f;
      EXPECT_GT(differ, 0) << count << " planes, p = " << p;
      // Rectangles 100 mm across hold every projection: the whole planes' values, bit for bit.
      for (std::size_t i = 0; i < std::size_t(count); ++i)
        if (!pieces[i].whole) {
          const Vec2 centre = s.planes[i].plane.toPlane(kCentre);
          pieces[i].rect = PlaneRect{centre - Vec2(50, 50), centre + Vec2(50, 50)};
        }
      EXPECT_EQ(shepardInterpolant(data, s.grid, p).value.values, whole.value.values) << count << " planes, p = " << p;
    }
}
