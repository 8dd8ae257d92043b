// Test fixtures: cutting planes with analytic sections (disks and annuli of spheres and shells).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "geometry/core/plane_of_pose.h"
#include "geometry/core/types.h"

namespace xsect::test {

/// `count` planes through uniform points of [-spread, spread]³ with normally drawn normals, from
/// `rng` (the draws in the order the compiler evaluates the arguments, as the tests measured).
inline std::vector<Plane> randomPlanes(std::mt19937& rng, int count, double spread) {
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(-spread, spread);
  std::vector<Plane> planes;
  for (int k = 0; k < count; ++k) planes.push_back(planeThrough(Vec3(u(rng), u(rng), u(rng)), Vec3(g(rng), g(rng), g(rng))));
  return planes;
}

/// The six faces of the box [lo, hi], normals outward.
inline std::vector<Plane> boxFaces(const Vec3& lo, const Vec3& hi) {
  std::vector<Plane> faces;
  for (int a = 0; a < 3; ++a) {
    faces.push_back(planeThrough(lo, -Vec3::Unit(a)));
    faces.push_back(planeThrough(hi, Vec3::Unit(a)));
  }
  return faces;
}

inline Ring circle(const Vec2& c, double r, int n, bool ccw = true) {
  Ring ring;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n * (ccw ? 1 : -1);
    ring.emplace_back(c.x() + r * std::cos(a), c.y() + r * std::sin(a));
  }
  return ring;
}

/// Axis-aligned plane through `offset` along `axis`, u/v the next two axes (right-handed).
inline Plane axisPlane(int axis, double offset) {
  Plane p;
  p.normal = Vec3::Unit(axis);
  p.u = Vec3::Unit((axis + 1) % 3);
  p.v = Vec3::Unit((axis + 2) % 3);
  p.origin = offset * p.normal;
  return p;
}

/// Sections of the shell Ri < |x - centre| < Ro (Ri = 0: a ball) by one plane.
/// A cutting plane observed over `extent` (plane coordinates, mm) at `pixel_mm`; a closing plane is
/// virtual (slice -1), any other takes `slice`.
inline CuttingPlane observedPlane(const Plane& plane, std::vector<Section> sections, const PlaneRect& extent,
                                  double pixel_mm, int slice, bool closing) {
  CuttingPlane cp;
  cp.slice = closing ? -1 : slice;
  cp.is_virtual = closing;
  cp.plane = plane;
  cp.sections = std::move(sections);
  cp.extent = extent;
  cp.pixel_mm = pixel_mm;
  return cp;
}

inline std::vector<Section> shellSections(const Plane& p, const Vec3& centre, double Ro, double Ri,
                                          int vertices = 256) {
  const double d = p.signedDistance(centre);
  std::vector<Section> out;
  if (std::abs(d) >= Ro) return out;
  const Vec2 c = p.toPlane(centre);
  const double ro = std::sqrt(Ro * Ro - d * d);
  Section s;
  s.outer = circle(c, ro, vertices);
  if (Ri > std::abs(d)) s.holes.push_back(circle(c, std::sqrt(Ri * Ri - d * d), vertices, false));
  out.push_back(s);
  return out;
}

/// `count` planes of uniformly random orientation, each at a uniform offset in [-spread, spread]
/// from `centre` along its normal, cut through the shell Ri < |x - centre| < Ro.
inline std::vector<CuttingPlane> randomShellPlanes(int count, std::mt19937_64& rng, const Vec3& centre,
                                                   double spread, double Ro, double Ri,
                                                   int vertices = 256) {
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(-spread, spread);
  std::vector<CuttingPlane> planes;
  for (int i = 0; i < count; ++i) {
    CuttingPlane cp;
    cp.slice = i;
    Vec3 n(g(rng), g(rng), g(rng));
    n.normalize();
    cp.plane.normal = n;
    cp.plane.u = n.unitOrthogonal();
    cp.plane.v = n.cross(cp.plane.u);
    cp.plane.origin = u(rng) * n + centre;
    cp.sections = shellSections(cp.plane, centre, Ro, Ri, vertices);
    planes.push_back(cp);
  }
  return planes;
}

/// Three orthogonal stacks of planes at the given spacing covering [-extent, extent].
inline std::vector<CuttingPlane> multiaxialShell(const Vec3& centre, double Ro, double Ri,
                                                 double spacing, double extent, double phase = 0.37) {
  std::vector<CuttingPlane> planes;
  for (int axis = 0; axis < 3; ++axis)
    for (double t = -extent + phase * spacing; t <= extent; t += spacing) {
      CuttingPlane cp;
      cp.slice = int(planes.size());
      cp.plane = axisPlane(axis, t + centre[axis]);
      cp.plane.origin = centre + t * Vec3::Unit(axis);
      cp.sections = shellSections(cp.plane, centre, Ro, Ri);
      planes.push_back(cp);
    }
  return planes;
}

/// A z-stack whose outermost sections are at zFirst and zLast, closed by virtual end planes at
/// `margin` beyond them: R ends half-way to those planes (Def. 16 in the closed end cells).
inline void expectEndsHalfWayToEndPlanes(const TriangleMesh& mesh, double zFirst, double zLast,
                                        double margin) {
  float zmin = 1e9f, zmax = -1e9f;
  for (const auto& v : mesh.vertices) zmin = std::min(zmin, v.z()), zmax = std::max(zmax, v.z());
  EXPECT_GT(zmax, zLast);
  EXPECT_LE(zmax, zLast + margin);
  EXPECT_LT(zmin, zFirst);
  EXPECT_GE(zmin, zFirst - margin);
  EXPECT_NEAR(zmax, zLast + margin / 2, 0.3);
  EXPECT_NEAR(zmin, zFirst - margin / 2, 0.3);
}

}  // namespace xsect::test
