// The planes' evidence about a sampled solid (geometry/reconstruction/plane_evidence.h): voxels
// beside a plane inside and outside its sections, against the definition on random oblique planes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/reconstruction/plane_evidence.h"
#include "geometry/scene/section_distance_field.h"
#include "section_fixtures.h"

using namespace xsect;

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
