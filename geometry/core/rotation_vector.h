// Rotations as rotation vectors (axis × angle in radians; so(3)), and back: for the small
// per-slice pose changes of stage 3 (geometry/conformity/pose_smoothing.h, pose_correction.h).
#pragma once

#include <Eigen/Geometry>

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

}  // namespace xsect
