// Rotations as rotation vectors (axis × angle in radians; so(3)), and back: for the small
// per-slice pose changes of stage 3 (geometry/conformity/pose_smoothing.h, pose_correction.h).
#pragma once

#include <Eigen/Geometry>
#include <cmath>

#include "geometry/core/types.h"

namespace xsect {

/// The rotation vector of a rotation matrix (angle in [0, π]).
inline Vec3 rotationVector(const Eigen::Matrix3d& r) {
  const Eigen::AngleAxisd aa(r);
  return aa.angle() * aa.axis();
}

/// The rotation matrix of a rotation vector (identity for the zero vector).
inline Eigen::Matrix3d rotationFromVector(const Vec3& w) {
  const double angle = w.norm();
  return angle > 0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
}

/// The left Jacobian of the rotation vector: R(w + dw) a = R(w) a - [R(w) a]x J(w) dw to first
/// order, J(w) = I + (1 - cos t)/t² [w]x + (t - sin t)/t³ [w]x² with t = |w| (series below 1e-4).
inline Eigen::Matrix3d rotationVectorLeftJacobian(const Vec3& w) {
  const double t2 = w.squaredNorm(), t = std::sqrt(t2);
  Eigen::Matrix3d k;
  k << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  const double a = t < 1e-4 ? 0.5 - t2 / 24 : (1 - std::cos(t)) / t2;
  const double b = t < 1e-4 ? 1.0 / 6 - t2 / 120 : (t - std::sin(t)) / (t2 * t);
  return Eigen::Matrix3d::Identity() + a * k + b * k * k;
}

}  // namespace xsect
