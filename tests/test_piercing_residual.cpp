// The piercing residual's Jacobian (geometry/conformity/piercing_residual.h), which pose
// correction hands to the solver in place of automatic differentiation: it must be the residual's
// derivative, at zero and at finite increments, and the residual must not change when both
// slices make the same rigid motion of the world (the gauge the prior fixes).
#include <gtest/gtest.h>

#include <random>

#include "geometry/conformity/piercing_residual.h"
#include "geometry/core/rotation_vector.h"

using namespace xsect;

namespace {

Vec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  return Vec3(g(rng), g(rng), g(rng)).normalized();
}

/// A random observation: points within 50 mm, the contour normal in plane `to`.
ContourPiercing randomObservation(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-50, 50);
  ContourPiercing o;
  o.point = Vec3(u(rng), u(rng), u(rng));
  o.nearest = o.point + 0.05 * Vec3(u(rng), u(rng), u(rng));
  o.plane_normal = randomUnit(rng);
  o.tangent = (o.plane_normal + 0.8 * randomUnit(rng)).normalized();  // away from plane `to`
  o.contour_normal = o.plane_normal.cross(randomUnit(rng)).normalized();
  return o;
}

}  // namespace

TEST(PiercingResidual, JacobianIsTheDerivativeAtZeroAndFiniteIncrements) {
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> small(-0.3, 0.3), shift(-5, 5);
  int checked = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const ContourPiercing o = randomObservation(rng);
    const PiercingPivots pivots{Vec3(shift(rng), shift(rng), shift(rng)), Vec3(shift(rng), shift(rng), shift(rng))};
    std::array<double, 12> x{};
    if (trial % 2)  // half at zero increments (how the fit starts each round), half away from it
      for (int k = 0; k < 12; ++k) x[std::size_t(k)] = (k / 3) % 2 ? shift(rng) : small(rng);
    double r = 0;
    Eigen::Matrix<double, 1, 12> jac;
    if (!piercingResidual(o, pivots, 4.0, &x[0], &x[3], &x[6], &x[9], &r, &jac)) continue;
    for (int k = 0; k < 12; ++k) {
      const double h = 1e-6;
      std::array<double, 12> a = x, b = x;
      a[std::size_t(k)] += h;
      b[std::size_t(k)] -= h;
      double ra = 0, rb = 0;
      ASSERT_TRUE(piercingResidual(o, pivots, 4.0, &a[0], &a[3], &a[6], &a[9], &ra, nullptr));
      ASSERT_TRUE(piercingResidual(o, pivots, 4.0, &b[0], &b[3], &b[6], &b[9], &rb, nullptr));
      const double numeric = (ra - rb) / (2 * h);
      EXPECT_NEAR(jac[k], numeric, 1e-5 * (1 + std::abs(numeric))) << "trial " << trial << " entry " << k;
    }
    ++checked;
  }
  EXPECT_GT(checked, 450);
}

TEST(PiercingResidual, AtZeroItIsThePiercingDistanceAndAWorldMotionChangesNothing) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> small(-0.3, 0.3), shift(-20, 20);
  for (int trial = 0; trial < 200; ++trial) {
    const ContourPiercing o = randomObservation(rng);
    const PiercingPivots pivots{Vec3(shift(rng), shift(rng), shift(rng)), Vec3(shift(rng), shift(rng), shift(rng))};
    const double zero[3] = {0, 0, 0};
    double r0 = 0;
    ASSERT_TRUE(piercingResidual(o, pivots, 2.0, zero, zero, zero, zero, &r0, nullptr));
    EXPECT_NEAR(r0, 2.0 * piercingDistance(o), 1e-9);
    // x -> R x + c for both slices: increments w (the same) and t = c + (R - I) pivot.
    const Vec3 w(small(rng), small(rng), small(rng)), c(shift(rng), shift(rng), shift(rng));
    const Eigen::Matrix3d R = rotationFromVector(w);
    const Vec3 tf = c + (R - Eigen::Matrix3d::Identity()) * pivots.from;
    const Vec3 tt = c + (R - Eigen::Matrix3d::Identity()) * pivots.to;
    double r = 0;
    ASSERT_TRUE(piercingResidual(o, pivots, 2.0, w.data(), tf.data(), w.data(), tt.data(), &r, nullptr));
    EXPECT_NEAR(r, r0, 1e-9 * (1 + std::abs(r0)));
    // One slice alone moving does change it (the residual is not blind).
    ASSERT_TRUE(piercingResidual(o, pivots, 2.0, w.data(), tf.data(), zero, zero, &r, nullptr));
    EXPECT_GT(std::abs(r - r0), 1e-6);
  }
}
