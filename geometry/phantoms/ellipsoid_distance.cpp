// Closest point on an ellipsoid (see ellipsoid_distance.h). The problem is reduced by symmetry to
// the first octant with axes sorted e0 >= e1 >= e2. When y2 > 0 the closest point is
// x_i = e_i^2 y_i / (t + e_i^2) where t > -e2^2 is the root of
//   F(t) = sum_i (e_i y_i / (t + e_i^2))^2 - 1,
// strictly decreasing on (-e2^2, inf). We bisect in u = t + e2^2 > 0 (so that t + e_i^2 =
// u + (e_i^2 - e2^2) keeps full relative precision near the centre). When y2 = 0 the closest point
// either leaves the plane x2 = 0 (points inside the evolute region) or is the closest point of the
// ellipse (e0, e1) in that plane: the same argument one dimension lower.
#include "geometry/phantoms/ellipsoid_distance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace xsect {
namespace {

/// Root u > 0 of sum_i (e_i y_i / (u + d_i))^2 = 1 where d_i = e_i^2 - e_last^2 >= 0 and
/// y_last > 0. Bisection until the interval cannot shrink in double precision.
template <int N>
double bisectRoot(const std::array<double, N>& e, const std::array<double, N>& y) {
  std::array<double, N> d;
  for (int i = 0; i < N; ++i) d[i] = e[i] * e[i] - e[N - 1] * e[N - 1];
  auto F = [&](double u) {
    double s = 0.0;
    for (int i = 0; i < N; ++i) {
      const double q = e[i] * y[i] / (u + d[i]);
      s += q * q;
    }
    return s - 1.0;
  };
  double lo = e[N - 1] * y[N - 1];  // F(lo) >= 0: the last term alone is 1
  double norm = 0.0;
  for (int i = 0; i < N; ++i) norm += (e[i] * y[i]) * (e[i] * y[i]);
  double hi = e[N - 1] * e[N - 1] + std::sqrt(norm);  // t = |e*y| gives F <= 0
  hi = std::max(hi, lo);
  for (int it = 0; it < 2000; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    if (F(mid) > 0.0)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

/// Closest point of the ellipse x0^2/e0^2 + x1^2/e1^2 = 1 (e0 >= e1 > 0) to y (y >= 0).
std::array<double, 2> closestOnEllipse(const std::array<double, 2>& e,
                                       const std::array<double, 2>& y) {
  if (y[1] > 0.0) {
    if (y[0] <= 0.0) return {0.0, e[1]};
    const double u = bisectRoot<2>(e, y);
    const double d0 = e[0] * e[0] - e[1] * e[1];
    return {e[0] * e[0] * y[0] / (u + d0), e[1] * e[1] * y[1] / u};
  }
  // y1 = 0: inside the evolute segment the closest point leaves the axis.
  const double d0 = e[0] * e[0] - e[1] * e[1];
  if (d0 > 0.0 && e[0] * y[0] < d0) {
    const double x0 = e[0] * e[0] * y[0] / d0;
    const double r = x0 / e[0];
    return {x0, e[1] * std::sqrt(std::max(0.0, 1.0 - r * r))};
  }
  return {e[0], 0.0};
}

}  // namespace

double ellipsoidSignedDistance(const Vec3& semi_axes, const Vec3& point, Vec3* closest) {
  // Sort axes decreasing; remember the permutation and the signs.
  std::array<int, 3> order{0, 1, 2};
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return semi_axes[a] > semi_axes[b]; });
  std::array<double, 3> e, y;
  for (int k = 0; k < 3; ++k) {
    e[k] = semi_axes[order[k]];
    y[k] = std::abs(point[order[k]]);
  }
  std::array<double, 3> x{0, 0, 0};
  if (y[2] > 0.0) {
    const double u = bisectRoot<3>(e, y);
    for (int k = 0; k < 3; ++k) {
      const double dk = e[k] * e[k] - e[2] * e[2];
      x[k] = e[k] * e[k] * y[k] / (u + dk);
    }
  } else {
    bool offPlane = false;
    if (e[1] > e[2]) {
      // Candidate with t = -e2^2: x_i = e_i^2 y_i / (e_i^2 - e2^2), i = 0, 1.
      double s = 0.0;
      std::array<double, 2> c{};
      for (int k = 0; k < 2; ++k) {
        const double dk = e[k] * e[k] - e[2] * e[2];
        c[k] = e[k] * e[k] * y[k] / dk;
        s += (c[k] / e[k]) * (c[k] / e[k]);
      }
      if (s < 1.0) {
        x = {c[0], c[1], e[2] * std::sqrt(1.0 - s)};
        offPlane = true;
      }
    }
    if (!offPlane) {
      const auto q = closestOnEllipse({e[0], e[1]}, {y[0], y[1]});
      x = {q[0], q[1], 0.0};
    }
  }
  double dist2 = 0.0, level = 0.0;
  for (int k = 0; k < 3; ++k) {
    dist2 += (y[k] - x[k]) * (y[k] - x[k]);
    level += (y[k] / e[k]) * (y[k] / e[k]);
  }
  if (closest) {
    for (int k = 0; k < 3; ++k)
      (*closest)[order[k]] = std::copysign(x[k], point[order[k]]);
  }
  const double d = std::sqrt(dist2);
  return level < 1.0 ? -d : d;
}

}  // namespace xsect
