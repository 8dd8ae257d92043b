// Exact Euclidean distance from a point to an axis-aligned ellipsoid surface, by a robust
// closest-point computation (the bisection approach described by D. Eberly, "Distance from a
// point to an ellipse, an ellipsoid, or a hyperellipsoid": the closest point x satisfies
// x_i = e_i^2 y_i / (t + e_i^2) for the unique root t of a monotone function, found by bisection).
#pragma once

#include "geometry/core/types.h"

namespace xsect {

/// @param semi_axes  semi-axis lengths (a, b, c) along x, y, z in mm; all > 0.
/// @param y          query point in the ellipsoid's frame (centred at the origin), mm.
/// @param closest    out (optional): the closest point of the surface, mm.
/// @return           signed distance in mm (negative inside).
double ellipsoidSignedDistance(const Vec3& semi_axes, const Vec3& y, Vec3* closest = nullptr);

}  // namespace xsect
