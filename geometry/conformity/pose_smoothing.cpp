// Local quadratic regression of a sweep's poses (see pose_smoothing.h).
#include "geometry/conformity/pose_smoothing.h"

#include "geometry/core/median.h"
#include "geometry/core/rotation_vector.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace xsect {
namespace {

constexpr double kMaxTurnDeg = 5.0;
constexpr double kMaxJumpSteps = 10.0;
constexpr int kRobustPasses = 2;
constexpr int kMaxGlitchFrames = 3;
/// Corrections below this are tracker noise, never a glitch: the bisquare scale is at least this.
constexpr double kMinOutlierMm = 0.5;

Eigen::Matrix3d rotationOf(const Plane& p) {
  Eigen::Matrix3d r;
  r.col(0) = p.u;
  r.col(1) = p.v;
  r.col(2) = p.normal;
  return r;
}


/// Each frame's sweep (0, 1, ...): a new one starts where consecutive frames turn by more than
/// kMaxTurnDeg or their reference points jump by more than kMaxJumpSteps times the median step.
std::vector<int> sweepOfFrames(const std::vector<Plane>& planes, const std::vector<Vec2>& reference) {
  const int n = int(planes.size());
  // Steps between frames i - 1 and i, of frame i's reference point (one point of the image).
  std::vector<double> step(std::size_t(n), 0.0);
  for (int i = 1; i < n; ++i)
    step[std::size_t(i)] = (planes[std::size_t(i)].toWorld(reference[std::size_t(i)]) -
                            planes[std::size_t(i - 1)].toWorld(reference[std::size_t(i)])).norm();
  const double medianStep = upperMedian(std::vector<double>(step.begin() + 1, step.end()));
  // Whether frames a < b continue one sweep (b - a steps apart).
  const auto continues = [&](int a, int b) {
    const double turn = Eigen::AngleAxisd(rotationOf(planes[std::size_t(a)]).transpose() *
                                          rotationOf(planes[std::size_t(b)])).angle();
    const double jump = (planes[std::size_t(b)].toWorld(reference[std::size_t(b)]) -
                         planes[std::size_t(a)].toWorld(reference[std::size_t(b)])).norm();
    return turn <= (b - a) * kMaxTurnDeg * M_PI / 180 && jump <= (b - a) * kMaxJumpSteps * medianStep + 1e-9;
  };
  std::vector<char> breaks(std::size_t(n), 0);  // breaks[i]: a new sweep starts at frame i
  for (int i = 1; i < n; ++i) breaks[std::size_t(i)] = !continues(i - 1, i);
  // A run of at most kMaxGlitchFrames frames cut off on both sides, between frames that continue
  // each other, is a glitch inside one sweep (left to the robust passes), not a sweep of its own.
  for (int a = 1; a < n; ++a) {
    if (!breaks[std::size_t(a)]) continue;
    for (int b = a + 1; b <= std::min(n - 1, a + kMaxGlitchFrames); ++b)
      if (breaks[std::size_t(b)] && continues(a - 1, b)) {
        breaks[std::size_t(a)] = breaks[std::size_t(b)] = 0;
        break;
      }
  }
  std::vector<int> sweep(std::size_t(n), 0);
  for (int i = 1; i < n; ++i) sweep[std::size_t(i)] = sweep[std::size_t(i - 1)] + breaks[std::size_t(i)];
  return sweep;
}

}  // namespace

PoseSmoothing smoothPoseTrajectory(const std::vector<Plane>& planes, const std::vector<Vec2>& reference,
                                   int half_window) {
  if (reference.size() != planes.size())
    throw std::invalid_argument("smoothPoseTrajectory: one reference point per plane");
  if (half_window < 1) throw std::invalid_argument("smoothPoseTrajectory: half_window must be >= 1");
  const int n = int(planes.size());
  PoseSmoothing out;
  out.planes = planes;
  out.shift_mm.assign(planes.size(), 0.0);
  out.rotation_deg.assign(planes.size(), 0.0);
  out.robustness.assign(planes.size(), 1.0);
  if (n < 3) return out;

  const std::vector<int> sweep = sweepOfFrames(planes, reference);
  out.sweeps = sweep.back() + 1;

  // Lever arm turning a rotation residual into mm: the reference points' typical distance from
  // the origins (pixel (0, 0)), at least 1 mm.
  std::vector<double> arms;
  for (const Vec2& c : reference) arms.push_back(c.norm());
  const double lever = std::max(1.0, upperMedian(arms));

  std::vector<double> residual(std::size_t(n), 0.0);
  for (int pass = 0; pass <= kRobustPasses; ++pass) {
    if (pass > 0) {  // bisquare weights from the last pass's residuals (Cleveland 1979)
      const double scale = std::max(6 * upperMedian(residual), kMinOutlierMm);
      for (int j = 0; j < n; ++j) {
        const double u = residual[std::size_t(j)] / scale;
        out.robustness[std::size_t(j)] = u < 1 ? (1 - u * u) * (1 - u * u) : 0.0;
      }
    }
    for (int i = 0; i < n; ++i) {
      int lo = std::max(0, i - half_window), hi = std::min(n - 1, i + half_window);
      while (sweep[std::size_t(lo)] != sweep[std::size_t(i)]) ++lo;
      while (sweep[std::size_t(hi)] != sweep[std::size_t(i)]) --hi;
      // Weighted least squares of y = a + b d + c d²: the value at d = 0 is a = Σ ℓ_j y_j, with ℓ
      // the first row of (XᵀWX)⁻¹ XᵀW. Frames of zero weight are left out; three frames would fit
      // degree 2 exactly (no smoothing): below four, degree 1; below two, the frame as recorded.
      std::vector<int> used;
      std::vector<double> weight;
      for (int j = lo; j <= hi; ++j) {
        const double t = std::abs(double(j - i)) / (half_window + 1);
        const double w = std::pow(1 - t * t * t, 3) * out.robustness[std::size_t(j)];
        if (w > 0) used.push_back(j), weight.push_back(w);
      }
      const int m = int(used.size());
      if (m < 2) continue;
      const int degree = m >= 4 ? 2 : 1;
      Eigen::MatrixXd x(m, degree + 1);
      Eigen::VectorXd w(m);
      for (int q = 0; q < m; ++q) {
        w(q) = weight[std::size_t(q)];
        for (int k = 0; k <= degree; ++k) x(q, k) = std::pow(double(used[std::size_t(q)] - i), k);
      }
      const Eigen::MatrixXd xtw = x.transpose() * w.asDiagonal();
      const Eigen::RowVectorXd ell = (xtw * x).ldlt().solve(xtw).row(0);

      // Frame i's own reference point, followed through each neighbour's pose (the same point of
      // the probe's image in every frame), and the neighbours' rotations relative to frame i.
      const Vec2& c = reference[std::size_t(i)];
      const Eigen::Matrix3d ri = rotationOf(planes[std::size_t(i)]);
      Vec3 point = Vec3::Zero(), omega = Vec3::Zero();
      for (int q = 0; q < m; ++q) {
        const Plane& pj = planes[std::size_t(used[std::size_t(q)])];
        point += ell(q) * pj.toWorld(c);
        omega += ell(q) * rotationVector(ri.transpose() * rotationOf(pj));
      }
      const Eigen::Matrix3d r = ri * rotationFromVector(omega);
      Plane& p = out.planes[std::size_t(i)];
      p.u = r.col(0).normalized();
      p.normal = p.u.cross(r.col(1)).normalized();
      p.v = p.normal.cross(p.u);
      p.origin = point - c.x() * p.u - c.y() * p.v;
      out.shift_mm[std::size_t(i)] = (point - planes[std::size_t(i)].toWorld(c)).norm();
      out.rotation_deg[std::size_t(i)] = omega.norm() * 180.0 / M_PI;
      residual[std::size_t(i)] = out.shift_mm[std::size_t(i)] + lever * omega.norm();
    }
  }
  return out;
}

}  // namespace xsect
