// The piercing residual and its Jacobian (see piercing_residual.h).
#include "geometry/conformity/piercing_residual.h"

#include <cmath>

#include "geometry/core/rotation_vector.h"

namespace xsect {

bool piercingResidual(const ContourPiercing& obs, const PiercingPivots& pivots, double inv_noise, const double* w_f,
                      const double* t_f, const double* w_t, const double* t_t, double* r,
                      Eigen::Matrix<double, 1, 12>* jacobian) {
  const Vec3 wf(w_f[0], w_f[1], w_f[2]), wt(w_t[0], w_t[1], w_t[2]);
  const Eigen::Matrix3d Rf = rotationFromVector(wf), Rt = rotationFromVector(wt);
  const Vec3 xr = Rf * (obs.point - pivots.from), d = Rf * obs.tangent;
  const Vec3 yr = Rt * (obs.nearest - pivots.to), m = Rt * obs.contour_normal, n = Rt * obs.plane_normal;
  const Vec3 e = (pivots.from + xr + Vec3(t_f[0], t_f[1], t_f[2])) - (pivots.to + yr + Vec3(t_t[0], t_t[1], t_t[2]));
  const double pq = n.dot(e), nd = n.dot(d);
  if (!(std::abs(nd) >= 1e-9)) return false;
  const double s = -pq / nd;
  *r = (e + s * d).dot(m) * inv_noise;
  if (!jacobian) return true;
  // Gradients of r with respect to e, d, m and n (each varied alone), then chained through the
  // motions: d(R(w) a) = -[R(w) a]x J(w) dw, and g·(a x v) = (g x a)·v.
  const double dm = d.dot(m);
  const Vec3 ge = (m - (dm / nd) * n) * inv_noise;
  const Vec3 gd = (s * m + (pq * dm / (nd * nd)) * n) * inv_noise;
  const Vec3 gm = (e + s * d) * inv_noise;
  const Vec3 gn = (dm * (-e / nd + (pq / (nd * nd)) * d)) * inv_noise;
  const Eigen::Matrix3d Jf = rotationVectorLeftJacobian(wf), Jt = rotationVectorLeftJacobian(wt);
  jacobian->segment<3>(0) = (xr.cross(ge) + d.cross(gd)).transpose() * Jf;
  jacobian->segment<3>(3) = ge.transpose();
  jacobian->segment<3>(6) = (ge.cross(yr) + m.cross(gm) + n.cross(gn)).transpose() * Jt;
  jacobian->segment<3>(9) = -ge.transpose();
  return true;
}

}  // namespace xsect
