// Issue 14, the pieces under "the mesh written is the solid reported" and "scale-free defaults":
// the level set and mesh of a field keep its cavities and components (the cause of the lost
// cavity was OpenVDB's levelSetRebuild re-signing the band from the outside), the planes'
// evidence, the section width, and an automatic voxel size that scales with the data.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/reconstruction/automatic_voxel_size.h"
#include "geometry/core/digital_topology.h"
#include "geometry/meshing/mesh_topology.h"
#include "geometry/reconstruction/plane_evidence.h"
#include "geometry/scene/section_distance_field.h"
#include "geometry/reconstruction/section_width.h"
#include "geometry/meshing/volume_mesher.h"
#include "section_fixtures.h"

using namespace xsect;

namespace {

/// Dense field of the shell Ri < |x| < Ro (negative inside), not a distance beyond its scale:
/// (|x| - Ro)(|x| - Ri) / Ro, as smooth fields such as Shepard's are.
ScalarField shellField(double Ro, double Ri, double h) {
  ScalarField f;
  const int n = int(std::ceil(2 * (Ro + 3 * h) / h)) + 1;
  f.grid.voxel = h;
  f.grid.dims = {n, n, n};
  f.grid.origin = Vec3::Constant(-(n - 1) * h / 2);
  f.values.resize(std::size_t(f.grid.count()));
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double r = f.grid.centre(i, j, k).norm();
        f.values[std::size_t(f.grid.index(i, j, k))] = float((r - Ro) * (r - Ri) / Ro);
      }
  return f;
}

}  // namespace

TEST(LevelSetSurface, KeepsTheCavityOfAHollowField) {
  for (const double h : {0.25, 0.4, 0.6}) {
    SCOPED_TRACE(h);
    const ScalarField f = shellField(6.0, 3.5, h);
    const LevelSetSurface s = levelSetSurface(f, 3.0, 0.0);
    const MeshTopology t = meshTopology(s.mesh);
    EXPECT_TRUE(t.watertight);
    EXPECT_EQ(t.betti, (Betti{1, 0, 1}));
    // The band holds the inner surface: active voxels on both sides of r = Ri, signed as the
    // shell's (inside between the radii), their magnitude the distance to the surface.
    int innerInside = 0, innerOutside = 0;
    double worst = 0;
    for (std::size_t q = 0; q < s.level_set.coords.size(); ++q) {
      const auto& c = s.level_set.coords[q];
      const double r = s.level_set.grid.centre(c[0], c[1], c[2]).norm();
      const double sd = std::abs(r - 6.0) < std::abs(r - 3.5) ? r - 6.0 : 3.5 - r;
      if (std::abs(r - 3.5) < 2 * h) (s.level_set.values[q] < 0 ? innerInside : innerOutside)++;
      worst = std::max(worst, std::abs(double(s.level_set.values[q]) - sd));
    }
    EXPECT_GT(innerInside, 100);
    EXPECT_GT(innerOutside, 100);
    EXPECT_LT(worst, 0.5 * h);  // the mesh is within a fraction of a voxel of the spheres
  }
}

TEST(LevelSetSurface, MeshHasTheVoxelBettiNumbersOfAWellComposedSolid) {
  // Random blobs: the solid made well-composed, its mesh has the voxel set's Betti numbers.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 12; ++trial) {
    ScalarField f;
    f.grid.voxel = 1.0;
    f.grid.dims = {24, 24, 24};
    f.values.assign(std::size_t(f.grid.count()), 1.0f);
    std::vector<Vec3> centres;
    for (int b = 0; b < 10; ++b) centres.emplace_back(12 + 8 * u(rng), 12 + 8 * u(rng), 12 + 8 * u(rng));
    for (int k = 1; k < 23; ++k)
      for (int j = 1; j < 23; ++j)
        for (int i = 1; i < 23; ++i) {
          double v = 1e9;
          for (const Vec3& c : centres) v = std::min(v, (Vec3(i, j, k) - c).norm() - 2.6);
          f.values[std::size_t(f.grid.index(i, j, k))] = float(v);
        }
    std::vector<std::uint8_t> in(f.values.size());
    for (std::size_t q = 0; q < in.size(); ++q) in[q] = f.values[q] < 0;
    makeWellComposed(in, f.grid);
    imposeSolid(f, in, 0.05f);
    const LevelSetSurface s = levelSetSurface(f, 3.0, 0.0);
    const MeshTopology t = meshTopology(s.mesh);
    EXPECT_TRUE(t.watertight) << trial;
    EXPECT_EQ(t.betti, voxelBetti(in, f.grid)) << trial;
  }
}

TEST(ImposeSolid, ForcesTheSignToTheSet) {
  ScalarField f;
  f.grid.dims = {3, 1, 1};
  f.values = {-1.0f, 2.0f, 0.0f};
  const std::vector<std::uint8_t> in{0, 1, 1};
  EXPECT_EQ(imposeSolid(f, in, 0.1f), 3);
  EXPECT_EQ(f.values, (std::vector<float>{0.1f, -0.1f, -0.1f}));
}

TEST(PlaneEvidence, VoxelsBesideAPlaneInsideAndOutsideItsSection) {
  CuttingPlane p;
  p.plane = test::axisPlane(2, 0.05);
  Section s;
  s.outer = {{-3, -3}, {3, -3}, {3, 3}, {-3, 3}};
  p.sections = {s};
  const std::vector<CuttingPlane> planes{p};
  const std::vector<SectionDistanceField> fields{sectionDistanceField(p.sections, 0.1, 1.0)};
  GridSpec g;
  g.voxel = 0.5;
  g.origin = Vec3(-5, -5, -5);
  g.dims = {21, 21, 21};
  const PlaneEvidence e = planeEvidence(planes, fields, g, 0.5 * std::sqrt(3.0) * g.voxel, 0.5 * g.voxel);
  for (int k = 0; k < 21; ++k)
    for (int j = 0; j < 21; ++j)
      for (int i = 0; i < 21; ++i) {
        const Vec3 x = g.centre(i, j, k);
        const std::size_t q = std::size_t(g.index(i, j, k));
        const bool near = std::abs(x.z() - 0.05) <= 0.5 * std::sqrt(3.0) * g.voxel;
        const double inset = 3 - std::max(std::abs(x.x()), std::abs(x.y()));  // > 0 inside the square
        EXPECT_EQ(bool(e.inside[q]), near && inset >= 0.25 + 1e-6) << x.transpose();
        EXPECT_EQ(bool(e.outside[q]), near && inset <= -0.25 - 1e-6) << x.transpose();
      }
}

TEST(PlaneEvidence, EqualsTheDefinitionOnRandomObliquePlanes) {
  // Brute force: for every voxel, the nearest planes within reach decide (one inside suffices,
  // all must say outside). Plane 12 repeats plane 3 without its section, plane 13 plane 4.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  GridSpec g;
  g.voxel = 0.3;
  g.origin = Vec3(-3, -2.5, -3.2);
  g.dims = {21, 18, 23};
  std::vector<CuttingPlane> planes;
  std::vector<SectionDistanceField> fields;
  for (int k = 0; k < 12; ++k) {
    CuttingPlane p;
    const Vec3 n = Vec3(u(rng), u(rng), u(rng)).normalized();  // any sign, any obliquity
    p.plane.normal = n;
    p.plane.u = n.unitOrthogonal();
    p.plane.v = n.cross(p.plane.u);
    p.plane.origin = 2.0 * Vec3(u(rng), u(rng), u(rng));
    p.is_virtual = k == 11;
    if (k % 3 != 2 && !p.is_virtual) {
      Section s;
      s.outer = test::circle(Vec2(u(rng), u(rng)), 1.5 + u(rng), 64);
      p.sections = {s};
    }
    fields.push_back(sectionDistanceField(p.sections, 0.05, 1.0));
    planes.push_back(p);
  }
  for (const std::size_t k : {std::size_t(3), std::size_t(4)}) {
    CuttingPlane p = planes[k];
    if (k == 3) p.sections.clear();
    fields.push_back(sectionDistanceField(p.sections, 0.05, 1.0));
    planes.push_back(p);
  }
  const double near = 0.5 * std::sqrt(3.0) * g.voxel, margin = 0.5 * g.voxel;
  const PlaneEvidence e = planeEvidence(planes, fields, g, near, margin);
  int inside = 0, outside = 0;
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const Vec3 x = g.centre(i, j, k);
        double bestD = 1e300;
        for (std::size_t p = 0; p < planes.size(); ++p) {
          const double d = std::abs(planes[p].plane.signedDistance(x));
          if (d <= near) bestD = std::min(bestD, d);
        }
        bool in = false, out = bestD < 1e300;
        for (std::size_t p = 0; p < planes.size(); ++p) {
          const double d = std::abs(planes[p].plane.signedDistance(x));
          if (d > near || std::abs(d - bestD) > 1e-6 * g.voxel) continue;
          const Vec2 y = planes[p].plane.toPlane(x);
          const float f = fields[p].sample(y.x(), y.y());
          in = in || (f <= -margin && !planes[p].is_virtual);
          out = out && f >= margin;
        }
        const std::size_t q = std::size_t(g.index(i, j, k));
        EXPECT_EQ(bool(e.inside[q]), in) << x.transpose();
        EXPECT_EQ(bool(e.outside[q]), out) << x.transpose();
        inside += in;
        outside += out;
      }
  EXPECT_GT(inside, 50);  // the case is not vacuous
  EXPECT_GT(outside, 500);
}

TEST(SectionWidth, IsTheInscribedDiskDiameter) {
  // Within three raster steps, a step being the mean width 2A/P over 32 cells.
  Section disk;
  disk.outer = test::circle(Vec2(3, -2), 5.0, 256);
  EXPECT_NEAR(sectionWidth(disk), 10.0, 3 * 5.0 / 32);
  Section annulus = disk;
  annulus.holes = {test::circle(Vec2(3, -2), 3.0, 256, false)};
  EXPECT_NEAR(sectionWidth(annulus), 2.0, 3 * 2.0 / 32);
  for (const double w : {0.05, 0.5, 1.0, 2.0}) {
    Section strip;  // thin and long: the width, not the length, sets the raster
    strip.outer = {{0, 0}, {10, 0}, {10, w}, {0, w}};
    EXPECT_NEAR(sectionWidth(strip), w, 3 * w / 32 + 10.0 / 4096) << w;
  }
  Section empty;
  EXPECT_EQ(sectionWidth(empty), 0.0);
  EXPECT_THROW(sectionWidth(disk, 2), std::invalid_argument);
}

TEST(AutomaticVoxelSize, ScalesWithTheDataWhateverTheirUnit) {
  // Sections of a ball cut by three stacks, in units from 10^-3 to 10^3: the voxel size scales
  // with the data (to two significant digits) and the grid stays the same size.
  const auto scene = [](double scale) {
    std::vector<CuttingPlane> planes;
    for (int axis = 0; axis < 3; ++axis)
      for (int q = -3; q <= 3; ++q) {
        CuttingPlane p;
        p.plane = test::axisPlane(axis, scale * 1.7 * q);
        p.plane.origin += scale * Vec3(0.3, -0.2, 0.1);
        p.sections = test::shellSections(p.plane, scale * Vec3(0.3, -0.2, 0.1), scale * 6.0, 0.0);
        planes.push_back(p);
      }
    return planes;
  };
  const std::vector<CuttingPlane> unit = scene(1.0);
  const VoxelSizeChoice c1 = automaticVoxelSize(unit, sectionWidths(unit), {}, 4000000);
  EXPECT_GT(c1.voxel_mm, 0);
  for (const double scale : {1e-3, 0.037, 25.4, 1e3}) {
    SCOPED_TRACE(scale);
    const std::vector<CuttingPlane> planes = scene(scale);
    const VoxelSizeChoice c = automaticVoxelSize(planes, sectionWidths(planes), {}, 4000000);
    EXPECT_NEAR(c.voxel_mm / (scale * c1.voxel_mm), 1.0, 0.06);
    EXPECT_NEAR(double(c.voxels) / double(c1.voxels), 1.0, 0.25);
    EXPECT_EQ(c.limited_by, c1.limited_by);
  }
  // A budget the rule's size exceeds: the size grows until the grid fits.
  const VoxelSizeChoice small = automaticVoxelSize(unit, sectionWidths(unit), {}, 20000);
  EXPECT_EQ(small.limited_by, VoxelSizeLimit::voxel_budget);
  EXPECT_LE(small.voxels, 20000);
  EXPECT_GT(small.voxel_mm, c1.voxel_mm);
  EXPECT_THROW(automaticVoxelSize({}, {}, {}, 4000000), std::invalid_argument);
}

TEST(AutomaticVoxelSize, ThinSectionsGetAFinerGrid) {
  // Thin plates (1 unit thick, 40 across): the median width, not the bounds, decides.
  std::vector<CuttingPlane> planes;
  for (int q = 0; q < 8; ++q) {
    CuttingPlane p;
    p.plane = test::axisPlane(0, 5.0 * q);
    Section s;
    s.outer = {{0, 0}, {40, 0}, {40, 1}, {0, 1}};
    p.sections = {s};
    planes.push_back(p);
  }
  const VoxelSizeChoice c = automaticVoxelSize(planes, sectionWidths(planes), {}, 40000000);
  EXPECT_EQ(c.limited_by, VoxelSizeLimit::section_width);
  EXPECT_NEAR(c.voxel_mm, 0.25, 0.03);  // a quarter of the width, measured within 3 raster steps
}

TEST(TwoSignificantDigits, RoundsToNearestOrUp) {
  EXPECT_DOUBLE_EQ(twoSignificantDigits(0.01234), 0.012);
  EXPECT_DOUBLE_EQ(twoSignificantDigits(0.01234, true), 0.013);
  EXPECT_EQ(twoSignificantDigits(0.35, true), 0.35);  // the double nearest 0.35, no rounding noise
  EXPECT_EQ(twoSignificantDigits(0.4123), 0.41);
  EXPECT_EQ(twoSignificantDigits(1.7049), 1.7);
  EXPECT_DOUBLE_EQ(twoSignificantDigits(987.0), 990.0);
}
