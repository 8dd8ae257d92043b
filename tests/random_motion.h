// Random rigid motions for the tests that check a result does not depend on where and how a
// configuration is placed (rounding differs with every placement).
#pragma once

#include <Eigen/Geometry>
#include <random>

namespace xsect::test {

/// Rotation from three uniform angles (radians) about z, y and x.
inline Eigen::Matrix3d randomRotation(std::mt19937& rng) {
  std::uniform_real_distribution<double> angle(-3.14159, 3.14159);
  return (Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace xsect::test
