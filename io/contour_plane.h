// The frame of a plane of a contour file (.csl, .contour), from its equation and the vertices on
// it: normal the equation's, origin the vertices' mean (the equation's offset is not trusted),
// u, v completing a right-handed frame (u × v = normal).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "geometry/core/types.h"
#include "io/input_error.h"

namespace xsect {

/// The plane with unit normal `normal` through `vertices` (world mm, the file's vertices on this
/// plane): origin at their mean; each must lie within 1e-3 · (1 + |hi - lo|) mm of it, else
/// InputError(file, field, "vertices do not lie on one plane", line). Without vertices the plane
/// is normal · x + offset = 0 or normal · x - offset = 0 (`offset` in mm, of the normalised
/// equation), whichever lies nearer the centre of the data's bounds [lo, hi] (world mm, all the
/// file's vertices). u = normal × e_k normalised, e_k the first of the axes x, y with
/// |normal_k| < 0.6 (else z); v = normal × u.
inline Plane contourPlane(const Vec3& normal, double offset, const std::vector<Vec3>& vertices,
                          const Vec3& lo, const Vec3& hi, const std::string& file,
                          const std::string& field, int line) {
  Plane pl;
  pl.normal = normal;
  const int axis = std::abs(normal.x()) < 0.6 ? 0 : (std::abs(normal.y()) < 0.6 ? 1 : 2);
  pl.u = normal.cross(Vec3::Unit(axis)).normalized();
  pl.v = pl.normal.cross(pl.u);
  if (!vertices.empty()) {
    Vec3 m = Vec3::Zero();
    for (const auto& q : vertices) m += q;
    m /= double(vertices.size());
    pl.origin = m;
    for (const auto& q : vertices)
      if (std::abs(pl.signedDistance(q)) > 1e-3 * (1.0 + (hi - lo).norm()))
        throw InputError(file, field, "vertices do not lie on one plane", line);
  } else {
    // empty plane: choose the sign of the offset that brings it nearer the data
    const Vec3 centre = 0.5 * (lo + hi);
    const Vec3 a = -offset * normal, b = offset * normal;
    const double da = std::abs((centre - a).dot(normal)), db = std::abs((centre - b).dot(normal));
    pl.origin = da <= db ? a : b;
  }
  return pl;
}

}  // namespace xsect
