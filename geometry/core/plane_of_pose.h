// The cutting plane of a slice from its image_to_world pose (docs/inputs.md, conventions): origin is the
// centre of pixel (0, 0); u and v the normalised first two columns; normal = u x v. And a plane
// through a point with a given normal, with a frame completing it.
#pragma once

#include <cmath>
#include <string>

#include "geometry/core/types.h"

namespace xsect {

/// What makes `image_to_world` no pose a plane can be read from (empty when it is one): a last row
/// other than [0, 0, 0, 1], a zero or parallel or non-orthogonal first two columns.
inline std::string poseProblem(const Mat4& m) {
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
    return "last row must be [0, 0, 0, 1] (an affine pose)";
  const Vec3 c0 = m.block<3, 1>(0, 0), c1 = m.block<3, 1>(0, 1);
  if (c0.norm() < 1e-12 || c1.norm() < 1e-12) return "zero pixel spacing: the first two columns must be non-zero";
  if (c0.cross(c1).norm() < 1e-9 * c0.norm() * c1.norm())
    return "singular pose: the pixel axes (first two columns) are parallel";
  if (std::abs(c0.dot(c1)) > 1e-3 * c0.norm() * c1.norm()) return "pixel axes (first two columns) are not orthogonal";
  return "";
}

/// @param image_to_world 4x4, column vector (i, j, 0, 1) -> mm.
/// @param spacing        out: mm per pixel along i and j (the column norms).
/// Assumes a validated pose (finite, non-zero, orthogonal first two columns).
inline Plane planeOfPose(const Mat4& image_to_world, Vec2* spacing = nullptr) {
  Plane p;
  const Vec3 c0 = image_to_world.block<3, 1>(0, 0);
  const Vec3 c1 = image_to_world.block<3, 1>(0, 1);
  p.origin = image_to_world.block<3, 1>(0, 3);
  p.u = c0.normalized();
  p.normal = c0.cross(c1).normalized();
  p.v = p.normal.cross(p.u);  // exactly orthonormal, right-handed
  if (spacing) *spacing = Vec2(c0.norm(), c1.norm());
  return p;
}

/// The plane through `point` with unit normal along `normal` (non-zero); u, v complete a
/// right-handed orthonormal frame (u ⟂ the world axis least aligned with the normal among x, y).
inline Plane planeThrough(const Vec3& point, const Vec3& normal) {
  Plane p;
  p.origin = point;
  p.normal = normal.normalized();
  const Vec3 a = std::abs(p.normal.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  p.u = p.normal.cross(a).normalized();
  p.v = p.normal.cross(p.u);
  return p;
}

}  // namespace xsect
