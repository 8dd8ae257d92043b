// The residual of one contour piercing (contour_piercings.h) under increments of both slices'
// poses, and its exact Jacobian: the observation pose correction fits (pose_correction.h), in a
// form the solver evaluates without automatic differentiation (measured on two crossing sweeps of
// 200 frames, 65k piercings: the Jacobians took 0.7 of the stage's 2.6 s with dual numbers).
//
// With the increments (w_f, t_f) of slice `from` and (w_t, t_t) of slice `to` (rotation vectors
// about their pivots, radians; translations of the pivots, mm), every point x of a slice moves to
// pivot + R(w) (x - pivot) + t and every direction d to R(w) d. The residual is the piercing
// distance of the moved observation (piercingDistance) divided by the noise:
//   e = p - q, s = -(n·e) / (n·d), r = ((e + s d)·m) / noise
// with p, d the moved point and tangent of `from`, q, m, n the moved nearest point, contour normal
// and plane normal of `to`. Undefined (false) when the contour runs along plane `to` (|n·d| below
// 1e-9).
#pragma once

#include <Eigen/Core>

#include "geometry/conformity/contour_piercings.h"

namespace xsect {

struct PiercingPivots {
  Vec3 from = Vec3::Zero(), to = Vec3::Zero();  ///< the slices' pivots on their current poses, mm
};

/// r (above) at increments w_f, t_f, w_t, t_t (3 doubles each); when `jacobian` is not null, its
/// 12 entries are dr/d(w_f, t_f, w_t, t_t) in that order (per radian, per mm).
bool piercingResidual(const ContourPiercing& obs, const PiercingPivots& pivots, double inv_noise, const double* w_f,
                      const double* t_f, const double* w_t, const double* t_t, double* r,
                      Eigen::Matrix<double, 1, 12>* jacobian);

}  // namespace xsect
