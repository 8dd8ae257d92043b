// Pose smoothing of a tracked sweep (geometry/conformity/pose_smoothing.h): a trajectory with constant
// acceleration and a rotation whose vector is quadratic in time is kept exactly (degree 2 reproduces
// it, ends included), whatever the reference point of each frame; tracking jitter is reduced
// toward the true trajectory; a glitch is put back without pulling its neighbours; windows stop
// at a turn between sweeps; the planes stay orthonormal and right-handed; invalid arguments are
// refused.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <stdexcept>

#include "geometry/conformity/pose_smoothing.h"

namespace xsect {
namespace {

/// Frame i of a sweep along z: reference point at (1 + 0.002 i², 0.3 + 0.01 i, 0.06 i) mm, rotation
/// by 0.001 i + 2e-5 i² radians about a fixed oblique axis.
Plane trueFrame(int i, const Vec2& ref) {
  const Vec3 axis = Vec3(1, 2, 0.5).normalized();
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.001 * i + 2e-5 * i * i, axis).toRotationMatrix();
  Plane p;
  p.u = r.col(0);
  p.v = r.col(1);
  p.normal = r.col(2);
  const Vec3 point(1 + 0.002 * i * i, 0.3 + 0.01 * i, 0.06 * i);
  p.origin = point - ref.x() * p.u - ref.y() * p.v;
  return p;
}

/// The frame turned by r about its point `ref` (plane coordinates), then moved by `shift`.
Plane turned(Plane p, const Eigen::Matrix3d& r, const Vec2& ref, const Vec3& shift = Vec3::Zero()) {
  const Vec3 point = p.toWorld(ref) + shift;
  p.u = r * p.u;
  p.v = r * p.v;
  p.normal = r * p.normal;
  p.origin = point - ref.x() * p.u - ref.y() * p.v;
  return p;
}

double angleBetween(const Plane& a, const Plane& b) {
  Eigen::Matrix3d ra, rb;
  ra << a.u, a.v, a.normal;
  rb << b.u, b.v, b.normal;
  return Eigen::AngleAxisd(ra.transpose() * rb).angle();
}

TEST(PoseSmoothing, KeepsATrajectoryOfConstantAccelerationExactly) {
  const Vec2 ref(32, 24);
  std::vector<Plane> planes;
  for (int i = 0; i < 60; ++i) planes.push_back(trueFrame(i, ref));
  const PoseSmoothing s = smoothPoseTrajectory(planes, std::vector<Vec2>(planes.size(), ref), 8);
  ASSERT_EQ(s.planes.size(), planes.size());
  for (std::size_t i = 0; i < planes.size(); ++i) {
    EXPECT_LT((s.planes[i].toWorld(ref) - planes[i].toWorld(ref)).norm(), 1e-9) << i;
    // Relative to frame i the rotation is about the fixed axis by an angle quadratic in the
    // offset: its rotation vector is kept exactly too.
    EXPECT_LT(angleBetween(s.planes[i], planes[i]), 1e-9) << i;
    EXPECT_LT(s.shift_mm[i], 1e-9);
    EXPECT_LT(s.rotation_deg[i], 1e-7);
  }
}

TEST(PoseSmoothing, ReducesTrackingJitterTowardTheTrueSweep) {
  const Vec2 ref(32, 24);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<Plane> truth, recorded;
  for (int i = 0; i < 400; ++i) {
    truth.push_back(trueFrame(i, ref));
    // 0.05 mm per axis, 0.1 degree about a random axis through the reference point.
    const Vec3 axis = Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized();
    const Eigen::Matrix3d r = Eigen::AngleAxisd(0.1 * M_PI / 180 * gauss(rng), axis).toRotationMatrix();
    const Vec3 shift = 0.05 * Vec3(gauss(rng), gauss(rng), gauss(rng));
    recorded.push_back(turned(truth.back(), r, ref, shift));
  }
  // Error of a frame: how far its corners (the 64 x 48 mm image) are from the true ones.
  const auto error = [&](const std::vector<Plane>& planes) {
    double sum = 0;
    for (std::size_t i = 0; i < planes.size(); ++i)
      for (const Vec2 c : {Vec2(0, 0), Vec2(64, 0), Vec2(0, 48), Vec2(64, 48)})
        sum += (planes[i].toWorld(c) - truth[i].toWorld(c)).squaredNorm();
    return std::sqrt(sum / (4.0 * double(planes.size())));
  };
  const double before = error(recorded);
  const PoseSmoothing s = smoothPoseTrajectory(recorded, std::vector<Vec2>(recorded.size(), ref), 10);
  const double after = error(s.planes);
  // A local quadratic fit over 21 tricube-weighted frames keeps about 0.3 of the noise's standard
  // deviation at the centre of the sweep (more at its ends, where the window is one-sided).
  EXPECT_LT(after, 0.45 * before) << before << " -> " << after;
  for (const Plane& p : s.planes) {
    EXPECT_NEAR(p.u.norm(), 1.0, 1e-12);
    EXPECT_NEAR(p.v.norm(), 1.0, 1e-12);
    EXPECT_NEAR(p.u.dot(p.v), 0.0, 1e-12);
    EXPECT_LT((p.u.cross(p.v) - p.normal).norm(), 1e-12);
  }
  // The corrections reported are of the size of the jitter.
  double mean = 0;
  for (const double x : s.shift_mm) mean += x / double(s.shift_mm.size());
  EXPECT_GT(mean, 0.03);
  EXPECT_LT(mean, 0.15);
}

// Each frame's reference point is followed through its neighbours' poses: with a different
// reference per frame (a frame observed nowhere has its centre at the image corner) a smooth sweep
// is still kept, to within the third-order terms of the rotating points' paths (about 0.001 mm
// here: a point other than (32, 24) does not move quadratically). Fitting each neighbour's own
// reference point would mix points of the image up to 40 mm apart (errors of millimetres).
TEST(PoseSmoothing, DifferentReferencePointsPerFrameKeepASmoothSweep) {
  std::vector<Plane> planes;
  std::vector<Vec2> refs;
  for (int i = 0; i < 40; ++i) {
    planes.push_back(trueFrame(i, Vec2(32, 24)));
    refs.push_back(i % 7 == 3 ? Vec2(0, 0) : Vec2(32 + 0.1 * i, 24));
  }
  const PoseSmoothing s = smoothPoseTrajectory(planes, refs, 6);
  for (std::size_t i = 0; i < planes.size(); ++i)
    for (const Vec2 c : {Vec2(0, 0), Vec2(64, 48)})
      EXPECT_LT((s.planes[i].toWorld(c) - planes[i].toWorld(c)).norm(), 0.005) << i;
}

// A tracker glitch (one frame 10 mm and 3 degrees off) is found by the robust passes: weight 0,
// put back onto its neighbours' trajectory, and its neighbours are not pulled toward it.
TEST(PoseSmoothing, AGlitchIsPutBackWithoutPullingItsNeighbours) {
  const Vec2 ref(32, 24);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> gauss(0.0, 0.02);
  std::vector<Plane> truth, recorded;
  for (int i = 0; i < 100; ++i) {
    truth.push_back(trueFrame(i, ref));
    Plane p = truth.back();
    p.origin += Vec3(gauss(rng), gauss(rng), gauss(rng));
    recorded.push_back(p);
  }
  recorded[50] = turned(recorded[50], Eigen::AngleAxisd(3.0 * M_PI / 180, Vec3::UnitX()).toRotationMatrix(), ref,
                        Vec3(10, 0, 0));
  const PoseSmoothing s = smoothPoseTrajectory(recorded, std::vector<Vec2>(recorded.size(), ref), 10);
  EXPECT_EQ(s.sweeps, 1);
  EXPECT_EQ(s.robustness[50], 0.0);
  EXPECT_LT((s.planes[50].toWorld(ref) - truth[50].toWorld(ref)).norm(), 0.05);
  EXPECT_LT(angleBetween(s.planes[50], truth[50]), 0.1 * M_PI / 180);
  for (const int i : {45, 49, 51, 55}) {
    EXPECT_GT(s.robustness[std::size_t(i)], 0.0) << i;
    EXPECT_LT((s.planes[std::size_t(i)].toWorld(ref) - truth[std::size_t(i)].toWorld(ref)).norm(), 0.05) << i;
  }
}

// Two sweeps listed one after the other (the second turned by 90 degrees, as a second stack):
// windows stop at the turn, and each sweep, smooth on its own, is kept exactly.
TEST(PoseSmoothing, WindowsDoNotCrossSweeps) {
  const Vec2 ref(32, 24);
  const Eigen::Matrix3d quarter = Eigen::AngleAxisd(M_PI / 2, Vec3::UnitY()).toRotationMatrix();
  std::vector<Plane> planes;
  for (int i = 0; i < 30; ++i) planes.push_back(trueFrame(i, ref));
  for (int i = 0; i < 30; ++i) {
    const Plane p = trueFrame(i, ref);
    // The whole second sweep turned about the world origin: its reference point goes to
    // quarter · point + (0, 5, 0).
    const Vec3 point = p.toWorld(ref);
    planes.push_back(turned(p, quarter, ref, quarter * point + Vec3(0, 5, 0) - point));
  }
  const PoseSmoothing s = smoothPoseTrajectory(planes, std::vector<Vec2>(planes.size(), ref), 8);
  EXPECT_EQ(s.sweeps, 2);
  for (std::size_t i = 0; i < planes.size(); ++i) {
    EXPECT_LT((s.planes[i].toWorld(ref) - planes[i].toWorld(ref)).norm(), 1e-8) << i;
    EXPECT_LT(angleBetween(s.planes[i], planes[i]), 1e-8) << i;
  }
}

TEST(PoseSmoothing, RefusesInvalidArguments) {
  const std::vector<Plane> planes(5);
  EXPECT_THROW(smoothPoseTrajectory(planes, std::vector<Vec2>(4, Vec2::Zero()), 2), std::invalid_argument);
  EXPECT_THROW(smoothPoseTrajectory(planes, std::vector<Vec2>(5, Vec2::Zero()), 0), std::invalid_argument);
  // Two frames: nothing to fit, returned as given.
  const std::vector<Plane> two(2);
  EXPECT_EQ(smoothPoseTrajectory(two, std::vector<Vec2>(2, Vec2::Zero()), 3).shift_mm, std::vector<double>(2, 0.0));
}

}  // namespace
}  // namespace xsect
