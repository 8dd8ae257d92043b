// The smoothing step of thesis ch. 1 §1 on a voxel solid (level_set_smoothing.h): the smoothed
// surface keeps passing through the section-contours, is smoother than method 1's staircase, stops
// before the flow changes the connectivity the caller asks for, and does not depend on threads.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "geometry/core/digital_topology.h"
#include "geometry/smoothing/level_set_smoothing.h"
#include "geometry/evaluation/mesh_distance.h"
#include "geometry/meshing/mesh_topology.h"
#include "geometry/reconstruction/sampled_reconstruction.h"
#include "geometry/meshing/volume_mesher.h"
#include "section_fixtures.h"

using namespace xsect;

namespace {

/// Method 1 on a z-stack of disks whose radii jump from plane to plane: a staircase of cylinders
/// (each plane's disk extruded half-way to the next plane).
struct Staircase {
  std::vector<CuttingPlane> planes;
  std::vector<double> z, radius;
  SampledReconstruction rec;
  ScalarField field;                       // rec.field, dense
  std::vector<SectionDistanceField> near;  // one per real plane
};

Staircase staircase(double voxel = 0.5) {
  Staircase s;
  const double radii[] = {5.0, 7.5, 6.0, 8.5, 6.5, 8.0, 5.5};
  for (int i = 0; i < 7; ++i) {
    CuttingPlane cp;
    cp.slice = i;
    cp.plane = test::axisPlane(2, 3.1 * i);  // 6.2 voxels apart: at every fraction of a voxel
    Section sec;
    sec.outer = test::circle(Vec2(0, 0), radii[i], 256);
    cp.sections.push_back(sec);
    s.planes.push_back(cp);
    s.z.push_back(3.1 * i);
    s.radius.push_back(radii[i]);
  }
  ReconstructionParams p;
  p.voxel_mm = voxel;
  const SectionScene scene = sectionScene(s.planes, p);
  s.rec = reconstructOnGrid(scene);
  s.field = denseField(s.rec.field);
  s.near.assign(scene.fields.begin(), scene.fields.begin() + std::ptrdiff_t(s.planes.size()));
  return s;
}

/// Trilinear interpolation of the voxel values at x (world mm).
double trilinear(const ScalarField& f, const Vec3& x) {
  const Vec3 u = (x - f.grid.origin) / f.grid.voxel;
  int i0[3];
  double t[3];
  for (int a = 0; a < 3; ++a) {
    i0[a] = std::clamp(int(std::floor(u[a])), 0, f.grid.dims[a] - 2);
    t[a] = u[a] - i0[a];
  }
  double v = 0;
  for (int c = 0; c < 8; ++c) {
    const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
    const double w = (di ? t[0] : 1 - t[0]) * (dj ? t[1] : 1 - t[1]) * (dk ? t[2] : 1 - t[2]);
    v += w * f.at(i0[0] + di, i0[1] + dj, i0[2] + dk);
  }
  return v;
}

/// Largest |field| over points of every section-contour (the circles), mm.
double contourResidual(const ScalarField& f, const Staircase& s) {
  double worst = 0;
  for (std::size_t i = 0; i < s.z.size(); ++i)
    for (int a = 0; a < 90; ++a) {
      const double t = 2 * M_PI * a / 90;
      const Vec3 x(s.radius[i] * std::cos(t), s.radius[i] * std::sin(t), s.z[i]);
      worst = std::max(worst, std::abs(trilinear(f, x)));
    }
  return worst;
}

/// Roughness of the profile between the first and the last plane: Σ_k (r_{k+1} - r_k)² over the
/// voxel layers, r_k the radius of the disk with the area of layer k's solid (mm²). A stair of
/// height J counts J² where a ramp of the same height over n layers counts J²/n.
double profileRoughness(const ScalarField& f, double z0, double z1) {
  const GridSpec& g = f.grid;
  std::vector<double> r;
  for (int k = 0; k < g.dims[2]; ++k) {
    const double z = g.origin.z() + g.voxel * k;
    if (z < z0 || z > z1) continue;
    std::int64_t n = 0;
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) n += f.at(i, j, k) < 0;
    r.push_back(std::sqrt(double(n) * g.voxel * g.voxel / M_PI));
  }
  double sum = 0;
  for (std::size_t k = 1; k < r.size(); ++k) sum += (r[k] - r[k - 1]) * (r[k] - r[k - 1]);
  return sum;
}

int components(const ScalarField& f) {
  std::vector<std::uint8_t> inside(f.values.size());
  for (std::size_t q = 0; q < inside.size(); ++q) inside[q] = f.values[q] < 0;
  int count = 0;
  solidComponents(inside, f.grid, &count);
  return count;
}

/// Two balls (radius 6 mm) joined by a tube of radius `tube` mm along x, voxel 1 mm, as a field
/// clamped to ±3 mm; no planes.
ScalarField dumbbell(double tube) {
  ScalarField f;
  f.grid.voxel = 1.0;
  f.grid.dims = {44, 20, 20};
  f.values.resize(std::size_t(f.grid.count()));
  const Vec3 a(11, 9.5, 9.5), b(32, 9.5, 9.5);
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 44; ++i) {
        const Vec3 x(i, j, k);
        double d = std::min((x - a).norm() - 6, (x - b).norm() - 6);
        if (x.x() >= a.x() && x.x() <= b.x())
          d = std::min(d, std::hypot(x.y() - a.y(), x.z() - a.z()) - tube);
        f.values[std::size_t(f.grid.index(i, j, k))] = float(std::clamp(d, -3.0, 3.0));
      }
  return f;
}

}  // namespace

TEST(LevelSetSmoothing, SurfaceStillPassesThroughTheContours) {
  const Staircase s = staircase();
  const double h = s.field.grid.voxel;
  LevelSetSmoothingParams p;
  p.iterations = 0;
  const LevelSetSmoothing r0 = smoothSolidLevelSet(s.field, s.planes, s.near, p);
  p.iterations = 8;
  const LevelSetSmoothing r8 = smoothSolidLevelSet(s.field, s.planes, s.near, p);
  p.iterations = 20;
  const LevelSetSmoothing r20 = smoothSolidLevelSet(s.field, s.planes, s.near, p);
  // Nothing held (no planes given): the flow is free to move the contours.
  const LevelSetSmoothing f20 = smoothSolidLevelSet(s.field, {}, {}, p);
  const double e0 = contourResidual(r0.field, s), e8 = contourResidual(r8.field, s),
               e20 = contourResidual(r20.field, s), free20 = contourResidual(f20.field, s);
  std::printf("contour residual (mm): 0 steps %.4f, 8 steps %.4f, 20 steps %.4f, 20 free %.4f; "
              "held %lld\n",
              e0, e8, e20, free20, (long long)r8.held_voxels);
  EXPECT_EQ(r8.iterations_applied, 8);
  EXPECT_GT(r8.held_voxels, 0);
  EXPECT_EQ(f20.held_voxels, 0);
  EXPECT_LT(e0, 0.5 * h);
  EXPECT_LT(e8, 0.5 * h);
  EXPECT_LT(e20, 0.5 * h);
  EXPECT_GT(free20, 0.5 * h);  // the hold is what keeps the surface on the contours
}

TEST(LevelSetSmoothing, SmoothsTheStaircase) {
  const Staircase s = staircase();
  const float band = float(3 * s.field.grid.voxel);
  LevelSetSmoothingParams p;
  p.iterations = 0;
  const LevelSetSmoothing r0 = smoothSolidLevelSet(s.field, s.planes, s.near, p);
  p.iterations = 8;
  const LevelSetSmoothing r8 = smoothSolidLevelSet(s.field, s.planes, s.near, p);
  // Step 0 is the input re-distanced: the same voxel solid.
  ASSERT_EQ(r0.field.values.size(), s.field.values.size());
  for (std::size_t q = 0; q < r0.field.values.size(); ++q)
    ASSERT_EQ(r0.field.values[q] < 0, s.field.values[q] < 0) << q;
  // Values: distances within the band, ±band beyond, the right sign deep inside and outside.
  for (const LevelSetSmoothing* r : {&r0, &r8}) {
    const auto [lo, hi] = std::minmax_element(r->field.values.begin(), r->field.values.end());
    EXPECT_EQ(*lo, -band);
    EXPECT_EQ(*hi, band);
    const GridSpec& g = r->field.grid;
    const Vec3 u = (Vec3(0, 0, 9.3) - g.origin) / g.voxel;  // on the axis, mid-stack
    EXPECT_EQ(r->field.at(int(std::lround(u.x())), int(std::lround(u.y())), int(std::lround(u.z()))), -band);
    EXPECT_EQ(r->field.at(0, 0, 0), band);
  }
  const double a_in = surfaceArea(meshZeroLevel(s.field)), a0 = surfaceArea(meshZeroLevel(r0.field)),
               a8 = surfaceArea(meshZeroLevel(r8.field));
  const double g_in = profileRoughness(s.field, s.z.front(), s.z.back()),
               g0 = profileRoughness(r0.field, s.z.front(), s.z.back()),
               g8 = profileRoughness(r8.field, s.z.front(), s.z.back());
  std::printf("area (mm2): input %.2f, 0 steps %.2f, 8 steps %.2f; roughness (mm2): input %.3f, "
              "0 steps %.3f, 8 steps %.3f\n",
              a_in, a0, a8, g_in, g0, g8);
  EXPECT_LT(a8, 0.92 * a0);  // measured: -14%
  const MeshTopology topo = meshTopology(meshZeroLevel(r8.field));
  EXPECT_TRUE(topo.watertight);
  EXPECT_EQ(topo.betti, (Betti{1, 0, 0}));
  EXPECT_LT(g8, 0.5 * g0);   // measured: 27.2 -> 6.9 mm²
}

TEST(LevelSetSmoothing, KeepsStopsBeforeTheNeckPinches) {
  // Tube radius 0.75 voxel (1.5 voxels thick): the first step pinches it. Radius 1.5: a few steps.
  for (const double tube : {0.75, 1.5}) {
    SCOPED_TRACE(tube);
    const ScalarField f = dumbbell(tube);
    ASSERT_EQ(components(f), 1);
    LevelSetSmoothingParams p;
    p.iterations = 8;
    const LevelSetSmoothing free = smoothSolidLevelSet(f, {}, {}, p);
    int calls = 0;
    const auto oneComponent = [&](const std::vector<std::uint8_t>& in) {
      ++calls;
      int n = 0;
      solidComponents(in, f.grid, &n);
      return n == 1;
    };
    const LevelSetSmoothing kept = smoothSolidLevelSet(f, {}, {}, p, oneComponent);
    std::printf("tube radius %.2f voxel: without keeps %d components after 8 steps; with keeps %d "
                "component after %d steps (%d calls)\n",
                tube, components(free.field), components(kept.field), kept.iterations_applied, calls);
    EXPECT_EQ(free.iterations_applied, 8);
    EXPECT_EQ(components(free.field), 2);  // the flow pinches the neck...
    EXPECT_LT(kept.iterations_applied, 8);  // ...so keeps stops it
    EXPECT_EQ(components(kept.field), 1);
    EXPECT_EQ(calls, kept.iterations_applied + 1);  // stopped at the first rejection
    if (tube > 1) EXPECT_GT(kept.iterations_applied, 0);
    // The result is exactly the flow stopped after iterations_applied steps.
    p.iterations = kept.iterations_applied;
    const LevelSetSmoothing again = smoothSolidLevelSet(f, {}, {}, p);
    EXPECT_EQ(again.field.values, kept.field.values);
  }
}

TEST(LevelSetSmoothing, RejectsMismatchedInputs) {
  const ScalarField f = dumbbell(1.5);
  LevelSetSmoothingParams p;
  std::vector<CuttingPlane> planes(1);
  EXPECT_THROW(smoothSolidLevelSet(f, planes, {}, p), std::invalid_argument);
  ScalarField bad = f;
  bad.values.pop_back();
  EXPECT_THROW(smoothSolidLevelSet(bad, {}, {}, p), std::invalid_argument);
  p.half_width_voxels = 1;
  EXPECT_THROW(smoothSolidLevelSet(f, {}, {}, p), std::invalid_argument);
}

TEST(LevelSetSmoothing, SameBytesForAnyThreadCount) {
  const Staircase s = staircase();
  LevelSetSmoothingParams p;
  LevelSetSmoothing one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = smoothSolidLevelSet(s.field, s.planes, s.near, p);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = smoothSolidLevelSet(s.field, s.planes, s.near, p);
  }
  ASSERT_EQ(one.field.values.size(), two.field.values.size());
  EXPECT_EQ(std::memcmp(one.field.values.data(), two.field.values.data(),
                        one.field.values.size() * sizeof(float)),
            0);
  EXPECT_EQ(one.iterations_applied, two.iterations_applied);
}
