// Points of the zero set of an implicit function f (a phantom's signed distance): Newton's
// projection x <- x - f grad f / |grad f|^2 onto f = 0, and the descent from a point of the surface
// to a local minimum of the distance to q (tangent steps toward q, projected back, halved until the
// distance decreases). The phantoms' exact distances (phantom_shape.cpp, vessel_tree.cpp) are
// polished with them.
//
// Surface: s.value(x) -> double, s.gradient(x) -> Vec3 (of f at x), s.check(x) -> double (the
// value by which the last Newton iterate is accepted).
#pragma once

#include <algorithm>
#include <cmath>

#include "geometry/core/types.h"

namespace xsect {

struct ImplicitSurfaceSteps {
  double converged = 1e-10;  ///< |f| below which a Newton iterate is on the surface, mm
  double accepted = 1e-8;    ///< |check| accepted after the last of 60 Newton steps, mm
  int descent_steps = 200;   ///< tangent steps of the descent at most
  double min_gain = 1e-12;   ///< the descent stops after a step gaining less, mm
};

/// Newton steps from x onto f = 0; false (out untouched) when they do not converge.
template <typename Surface>
bool projectOntoSurface(const Surface& s, Vec3 x, const ImplicitSurfaceSteps& k, Vec3* out) {
  for (int it = 0; it < 60; ++it) {
    const double f = s.value(x);
    if (!std::isfinite(f)) return false;
    if (std::abs(f) < k.converged) {
      *out = x;
      return true;
    }
    const Vec3 g = s.gradient(x);
    const double g2 = g.squaredNorm();
    if (!(g2 > 1e-20)) return false;
    x -= (f / g2) * g;
  }
  if (!(std::abs(s.check(x)) < k.accepted)) return false;
  *out = x;
  return true;
}

/// From p on the surface, a local minimum of |x - q| over the surface.
template <typename Surface>
Vec3 descendToNearest(const Surface& s, const Vec3& q, Vec3 p, const ImplicitSurfaceSteps& k) {
  double dist = (q - p).norm(), lambda = 1.0;
  for (int it = 0; it < k.descent_steps; ++it) {
    const Vec3 g = s.gradient(p);
    const double gn = g.norm();
    if (!(gn > 1e-12)) break;
    const Vec3 n = g / gn, w = q - p, t = w - w.dot(n) * n;
    if (t.norm() < 1e-12 * std::max(1.0, dist)) break;
    Vec3 c;
    bool moved = false;
    for (; lambda > 1e-9; lambda *= 0.5)
      if (projectOntoSurface(s, Vec3(p + lambda * t), k, &c) && (q - c).norm() < dist) {
        moved = true;
        break;
      }
    if (!moved) break;
    const double nd = (q - c).norm(), gain = dist - nd;
    p = c;
    dist = nd;
    lambda = std::min(1.0, 2.0 * lambda);
    if (gain < k.min_gain) break;
  }
  return p;
}

}  // namespace xsect
