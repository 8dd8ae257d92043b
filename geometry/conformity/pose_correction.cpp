// Robust least-squares pose correction from contour piercing distances (see pose_correction.h).
// Ceres Solver lives only in this translation unit.
#include "geometry/conformity/pose_correction.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "geometry/arrangement/plane_pair_traces.h"
#include "geometry/conformity/contour_piercings.h"
#include "geometry/conformity/piercing_residual.h"
#include "geometry/core/median.h"
#include "geometry/core/rotation_vector.h"

namespace xsect {
namespace {

constexpr double kDeg = M_PI / 180.0;
/// A direction is observable when its crossings' information is at least this fraction of the
/// prior's: below it, the posterior takes less than 5% of that component from the data
/// (shrinkage λ / (1 + λ)), and the correction there would be the prior's, not a measurement.
constexpr double kObservable = 0.05;

/// The piercing residual (piercing_residual.h) as Ceres sees it: one residual over the increments
/// (w, t) of slice `from`, then of slice `to`.
class PiercingCost final : public ceres::SizedCostFunction<1, 3, 3, 3, 3> {
 public:
  PiercingCost(const ContourPiercing& obs, const PiercingPivots& pivots, double inv_noise)
      : obs_(obs), pivots_(pivots), inv_noise_(inv_noise) {}
  bool Evaluate(double const* const* x, double* r, double** jacobians) const override {
    Eigen::Matrix<double, 1, 12> j;
    if (!piercingResidual(obs_, pivots_, inv_noise_, x[0], x[1], x[2], x[3], r, jacobians ? &j : nullptr))
      return false;
    if (jacobians)
      for (int b = 0; b < 4; ++b)
        if (jacobians[b])
          for (int k = 0; k < 3; ++k) jacobians[b][k] = j[3 * b + k];
    return true;
  }

 private:
  ContourPiercing obs_;
  PiercingPivots pivots_;
  double inv_noise_;
};

/// The prior on a slice's total correction (accumulated + increment).
struct PriorCost {
  Vec3 w0, t0;
  double inv_rad, inv_mm;
  template <typename T>
  bool operator()(const T* w, const T* t, T* r) const {
    for (int k = 0; k < 3; ++k) {
      r[k] = (T(w0[k]) + w[k]) * inv_rad;
      r[3 + k] = (T(t0[k]) + t[k]) * inv_mm;
    }
    return true;
  }
};

/// Consecutive frames of a sweep: their total corrections differ little.
struct TieCost {
  Vec3 dw0, dt0;  ///< accumulated difference (frame i - frame j)
  double inv_rad, inv_mm;
  template <typename T>
  bool operator()(const T* wi, const T* ti, const T* wj, const T* tj, T* r) const {
    for (int k = 0; k < 3; ++k) {
      r[k] = (T(dw0[k]) + wi[k] - wj[k]) * inv_rad;
      r[3 + k] = (T(dt0[k]) + ti[k] - tj[k]) * inv_mm;
    }
    return true;
  }
};


Plane movedPlane(const Plane& p, const Eigen::Matrix3d& R, const Vec3& pivot, const Vec3& t) {
  Plane q;
  q.origin = pivot + R * (p.origin - pivot) + t;
  q.u = R * p.u;
  q.v = R * p.v;
  q.normal = R * p.normal;
  return q;
}

double rms(const std::vector<double>& g) {
  double s = 0;
  for (const double x : g) s += x * x;
  return g.empty() ? 0.0 : std::sqrt(s / double(g.size()));
}
std::vector<double> absolute(std::vector<double> g) {
  for (double& x : g) x = std::abs(x);
  return g;
}

/// Piercing distances, per slice (both slices of each) and in all.
struct GapStats {
  std::vector<std::vector<double>> per_slice;
  std::vector<double> all;
};
GapStats gapStats(const std::vector<ContourPiercing>& observations, std::size_t slices) {
  GapStats s;
  s.per_slice.resize(slices);
  for (const ContourPiercing& o : observations) {
    const double g = piercingDistance(o);
    s.all.push_back(g);
    s.per_slice[std::size_t(o.from)].push_back(g);
    s.per_slice[std::size_t(o.to)].push_back(g);
  }
  return s;
}

/// "translation along normal", or along a direction given in (u, v, normal).
std::string directionName(const char* kind, const char* prep, const Vec3& local) {
  static const char* axes[3] = {"u", "v", "normal"};
  for (int k = 0; k < 3; ++k)
    if (std::abs(local[k]) > 0.98) return std::string(kind) + " " + prep + " " + axes[k];
  std::ostringstream s;
  s.precision(2);
  s << std::fixed << kind << " " << prep << " (" << local.x() << ", " << local.y() << ", " << local.z()
    << ") in (u, v, normal)";
  return s.str();
}

}  // namespace

Mat4 SliceCorrection::transform() const {
  const Eigen::Matrix3d R = rotationFromVector(rotation);
  Mat4 m = Mat4::Identity();
  m.block<3, 3>(0, 0) = R;
  m.block<3, 1>(0, 3) = pivot - R * pivot + translation;
  return m;
}

Plane correctedPlane(const Plane& recorded, const SliceCorrection& c) {
  return movedPlane(recorded, rotationFromVector(c.rotation), c.pivot, c.translation);
}

/// The fit of correctPoses, step by step: its scales, the sweep's ties and the outlier slices, the
/// rounds of each stage (Ceres), then each slice's information, observability and correction.
class PoseFit {
 public:
  PoseFit(const std::vector<CuttingPlane>& input, const std::vector<PlanePairTraces>& recordedPairs,
          const PoseCorrectionParams& params, PoseCorrection& out)
      : input_(input), recordedPairs_(recordedPairs), params_(params), out_(out), n_(input.size()),
        rigid_(params.kind == PoseCorrectionKind::rigid), planes_(input), R_(input.size(), Eigen::Matrix3d::Identity()),
        T_(input.size(), Vec3::Zero()), w_(input.size()), t_(input.size()) {}

  /// Pivots, radii, the measurement scale; false when there is nothing to measure by (no extent).
  bool measureScales() {
    const std::vector<CuttingPlane>& input = input_;
    const std::size_t n = n_;
    PoseCorrection& out = out_;
    std::vector<double> pixels, radii, halfDiagonals;
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (std::size_t i = 0; i < n; ++i) {
      const CuttingPlane& p = input[i];
      Vec3 sum = Vec3::Zero();
      std::size_t count = 0;
      for (const Section& s : p.sections)
        for (const Vec2& q : s.outer) {
          const Vec3 x = p.plane.toWorld(q);
          sum += x;
          ++count;
          lo = lo.cwiseMin(x);
          hi = hi.cwiseMax(x);
        }
      out.slices[i].pivot = count ? Vec3(sum / double(count)) : p.plane.toWorld(0.5 * (p.extent.min + p.extent.max));
      if (count) {
        std::vector<double> r;
        for (const Section& s : p.sections)
          for (const Vec2& q : s.outer) r.push_back((p.plane.toWorld(q) - out.slices[i].pivot).norm());
        radii.push_back(upperMedian(r));
      }
      if (p.pixel_mm > 0) pixels.push_back(p.pixel_mm);
      if (p.extent.max.x() > p.extent.min.x()) halfDiagonals.push_back(0.5 * (p.extent.max - p.extent.min).norm());
    }
    const double extent = (hi - lo).allFinite() && hi.x() >= lo.x() ? (hi - lo).norm() : 1.0;
    out.noise_mm = pixels.empty() ? 1e-3 * extent : 0.5 * upperMedian(pixels);
    if (!(out.noise_mm > 0) || !std::isfinite(out.noise_mm)) {  // no extent: nothing to measure by
      out.converged = true;
      return false;
    }
    radius_ = radii.empty() ? extent : std::max(upperMedian(radii), out.noise_mm);
    lever_ = std::max(radius_, halfDiagonals.empty() ? 0.0 : upperMedian(halfDiagonals));
    return true;
  }

  /// The prior's spreads, the gate of the piercings, their arc, and the sweep's ties: consecutive
  /// frames whose normals are within 5°.
  void setScalesAndTies() {
    const std::vector<PlanePairTraces>& recordedPairs = recordedPairs_;
    const PoseCorrectionParams& params = params_;
    const std::vector<CuttingPlane>& input = input_;
    const std::size_t n = n_;
    PoseCorrection& out = out_;
    std::vector<double> mismatch;
    for (const PlanePairTraces& p : recordedPairs) mismatch.push_back(p.disagreement.max_endpoint_mismatch_mm);
    cp_.arc_mm = 2 * out.noise_mm;  // a pixel each side
    // The gate's scale first: the pairs' largest endpoint mismatch (an endpoint slides along the
    // line by a shift over the planes' angle: wide, so that every true crossing passes).
    const double wide = std::max(mismatch.empty() ? 0.0 : upperMedian(mismatch), out.noise_mm);
    out.sigma_mm = params.sigma_mm ? *params.sigma_mm : std::max(piercingSpread(wide), out.noise_mm);
    out.sigma_deg = params.sigma_deg ? *params.sigma_deg : std::min(10.0, out.sigma_mm / lever_ / kDeg);
    out.gate_mm = 3 * (params.sigma_mm ? out.sigma_mm : wide) + 4 * out.noise_mm;
    sigmaRad_ = out.sigma_deg * kDeg;
    cp_.gate_mm = out.gate_mm;
    if (params.sweep_half_window > 0)
      for (std::size_t i = 0; i + 1 < n; ++i)
        if (input[i].plane.normal.dot(input[i + 1].plane.normal) > std::cos(5 * kDeg)) ties_.emplace_back(i, i + 1);
    tieScale_ = 1.0 / double(std::max(1, params.sweep_half_window));
  }

  /// A slice's shift per axis as the recorded piercings show it: the robust spread (1.4826 ×
  /// median) of their distances, gated at 3 `wide` + 4 noise, over √2 (a distance is the
  /// difference of two slices' shifts along one direction). Measured on thin tubes jittered by
  /// 0.6-1 mm: within 20% of the jitter, where the endpoint mismatch was 1.6-2.7 times it and let
  /// slices with few crossings turn by 10-27°.
  double piercingSpread(double wide) {
    PiercingParams gated = cp_;
    gated.gate_mm = 3 * wide + 4 * out_.noise_mm;
    recordedPiercings_ = contourPiercings(planes_, recordedPairs_, gated);  // round 0's, at the same gate
    std::vector<double> distances;
    for (const ContourPiercing& o : recordedPiercings_) distances.push_back(std::abs(piercingDistance(o)));
    return distances.empty() ? wide : 1.4826 * upperMedian(distances) / std::sqrt(2.0);
  }

  /// Outlier slices (a tracker glitch): a slice whose median disagreement over its pairs (their
  /// largest endpoint mismatch) exceeds 3 times the typical slice's and the gate, with at least 3
  /// pairs. Stage 1 corrects the other slices from the piercings among themselves; stage 2 corrects
  /// the outliers against them, held where stage 1 put them: an outlier cannot drag its partners.
  void findOutliers() {
    const std::vector<PlanePairTraces>& recordedPairs = recordedPairs_;
    const std::size_t n = n_;
    const PoseCorrection& out = out_;
    std::vector<std::vector<double>> pairMismatch(n);
    for (const PlanePairTraces& p : recordedPairs)
      for (const int i : {p.a, p.b}) pairMismatch[std::size_t(i)].push_back(p.disagreement.max_endpoint_mismatch_mm);
    std::vector<double> sliceMedians;
    for (const auto& m : pairMismatch)
      if (!m.empty()) sliceMedians.push_back(upperMedian(m));
    const double typical = sliceMedians.empty() ? 0.0 : upperMedian(sliceMedians);
    outlier_.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i)
      outlier_[i] = pairMismatch[i].size() >= 3 && upperMedian(pairMismatch[i]) > std::max(3 * typical, out.gate_mm);
    anyOutlier_ = std::find(outlier_.begin(), outlier_.end(), 1) != outlier_.end();
  }

  /// The stages' rounds: each round's piercings counted for the stage, the moves solved and applied,
  /// until they fall below a tenth of the noise. Returns whether every stage converged.
  bool fitStages() {
    const PoseCorrectionParams& params = params_;
    const std::size_t n = n_;
    const bool rigid = rigid_;
    PoseCorrection& out = out_;
    int round = 0;
    bool converged = true;  // every stage
    for (int stage = 0; stage < (anyOutlier_ ? 2 : 1); ++stage) {
      // free[i]: slice i's correction is estimated in this stage; an observation counts when it
      // involves a free slice and, in stage 1, no outlier.
      std::vector<char> free(n);
      for (std::size_t i = 0; i < n; ++i) free[i] = stage == 0 ? !outlier_[i] : outlier_[i];
      const auto counts = [&](const ContourPiercing& o) {
        const std::size_t a = std::size_t(o.from), b = std::size_t(o.to);
        return stage == 0 ? !outlier_[a] && !outlier_[b] : bool(outlier_[a] || outlier_[b]);
      };
      bool stageConverged = false;
      double previousMove = 0;  // the last full round's largest move (0: none yet)
      for (int stageRound = 0; stageRound < params.max_rounds; ++stageRound, ++round) {
        // Round 0 on the recorded poses: the piercings the automatic prior measured at this gate.
        const std::vector<ContourPiercing> observations =
            round == 0 && !recordedPiercings_.empty() ? std::move(recordedPiercings_)
            : round == 0 ? contourPiercings(planes_, recordedPairs_, cp_)
                         : contourPiercings(planes_, commonRegions(recordedPairs_, planes_), cp_);
        const GapStats gaps = gapStats(observations, n);
        if (round == 0) {
          out.crossings_before = int(observations.size());
          out.gap_before_mm = rms(gaps.all);
          out.median_gap_before_mm = gaps.all.empty() ? 0.0 : upperMedian(absolute(gaps.all));
          for (std::size_t i = 0; i < n; ++i) {
            out.slices[i].crossings_before = int(gaps.per_slice[i].size());
            out.slices[i].gap_before_mm = rms(gaps.per_slice[i]);
          }
        }
        std::vector<ContourPiercing> counted;
        for (const ContourPiercing& o : observations)
          if (counts(o)) counted.push_back(o);
        if (counted.empty()) {
          stageConverged = true;  // nothing to estimate
          break;
        }
        std::vector<double> distances;
        for (const ContourPiercing& o : counted) distances.push_back(std::abs(piercingDistance(o)));
        const double spread = 1.4826 * upperMedian(distances);
        out.robust_scale_mm = std::max(3 * spread, 3 * out.noise_mm);
        const bool translationOnly = !rigid || stageRound == 0;

        const std::vector<char> used = solveRound(counted, free, translationOnly);
        if (used.empty()) {
          stageConverged = false;
          break;
        }

        double largestMove = 0;
        for (std::size_t i = 0; i < n; ++i) {
          if (!used[i] || !free[i]) continue;
          const Vec3 dw(w_[i][0], w_[i][1], w_[i][2]), dt(t_[i][0], t_[i][1], t_[i][2]);
          const Eigen::Matrix3d dR = rotationFromVector(dw);
          planes_[i].plane = movedPlane(planes_[i].plane, dR, out.slices[i].pivot + T_[i], dt);
          R_[i] = dR * R_[i];
          T_[i] += dt;
          largestMove = std::max(largestMove, dt.norm() + dw.norm() * radius_);
        }
        out.rounds = round + 1;
        if (translationOnly && rigid) continue;  // the coarse round: its moves say nothing of the fit's
        // Converged when the moves left are below noise / 10: this round's move, or the rest of a
        // geometric decrease extrapolated from the last two rounds (move · q / (1 - q) with q their
        // ratio, trusted when q <= 1/2). Measured on two crossing sweeps of 200 frames: moves 0.16,
        // 0.014, 0.0028 mm (noise 0.1 mm); the extrapolation stops at 0.014 (rest 0.0013 mm) and saves
        // a round of 0.3 s whose move was below the tolerance anyway.
        const double q = previousMove > 0 ? largestMove / previousMove : 1.0;
        const double rest = q <= 0.5 ? largestMove * q / (1 - q) : largestMove;
        previousMove = largestMove;
        if (std::min(largestMove, rest) < 0.1 * out.noise_mm) {
          stageConverged = true;
          ++round;
          break;
        }
      }
      converged = converged && stageConverged;
      if (stage == 0 && !anyOutlier_) anyOutlier_ = findStranded();
    }
    keepBetterOfTwoFits();
    return converged;
  }

  /// A stranded slice keeps its refit only where the refit brought its piercings nearer (their
  /// RMS distance, which counts the far ones a median would hide); elsewhere it goes back to
  /// where the first stage left it, and is no outlier: a refit from the recorded pose may settle
  /// in another wrong minimum, and the slice keeps whichever pose its partners agree with better.
  void keepBetterOfTwoFits() {
    if (stranded_.empty()) return;
    const std::vector<double> now = sliceRms();
    for (const StrandedSlice& s : stranded_) {
      if (now[s.index] < s.rms) continue;
      planes_[s.index] = s.plane;
      R_[s.index] = s.R;
      T_[s.index] = s.T;
      outlier_[s.index] = 0;
    }
  }

  /// Per slice, the RMS distance of its piercings at the current poses (infinity: none).
  std::vector<double> sliceRms() const {
    const GapStats gaps = gapStats(contourPiercings(planes_, commonRegions(recordedPairs_, planes_), cp_), n_);
    std::vector<double> m(n_, std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < n_; ++i)
      if (!gaps.per_slice[i].empty()) m[i] = rms(gaps.per_slice[i]);
    return m;
  }

  /// Slices left behind by the first stage (a local minimum: their crossings matched to another
  /// section's contour, as on a vessel tree whose branches lie a jitter apart): the median
  /// distance of their piercings at the solution above the noise and 3 times the typical
  /// piercing's (at least 3 piercings), or a correction beyond 5 prior deviations (|τ|/σ_mm and
  /// |ω|/σ_rad together). Measured on a vessel tree (radii 2.5-4 mm) cut by 63 planes, jittered
  /// by 1 mm / 1°: one slice moved 3.6 mm and turned 5° the wrong way (median 0.15 mm where the
  /// others' are below 0.05), another ran 14 mm along its normal, past every crossing (its
  /// correction then unobservable, undone). They go back to their recorded poses and are fitted
  /// again in the outliers' stage, against the others held fixed.
  bool findStranded() {
    const std::vector<ContourPiercing> observations =
        contourPiercings(planes_, commonRegions(recordedPairs_, planes_), cp_);
    const GapStats gaps = gapStats(observations, n_);
    if (gaps.all.empty()) return false;
    const double typical = 1.4826 * upperMedian(absolute(gaps.all));
    const double limit = std::max(out_.noise_mm, 3 * typical);
    bool any = false;
    for (std::size_t i = 0; i < n_; ++i) {
      const bool apart = gaps.per_slice[i].size() >= 3 && upperMedian(absolute(gaps.per_slice[i])) > limit;
      const double prior = std::hypot(T_[i].norm() / out_.sigma_mm, rotationVector(R_[i]).norm() / sigmaRad_);
      if (!apart && !(prior > 5)) continue;
      outlier_[i] = 1;
      any = true;
      stranded_.push_back({i, planes_[i], R_[i], T_[i],
                           gaps.per_slice[i].empty() ? std::numeric_limits<double>::infinity()
                                                     : rms(gaps.per_slice[i])});
      planes_[i] = input_[i];
      R_[i] = Eigen::Matrix3d::Identity();
      T_[i] = Vec3::Zero();
    }
    return any;
  }

  /// One round's problem: every counted piercing (Cauchy loss), the sweep's ties and each used
  /// slice's prior; the free slices' corrections estimated (translations only in `translationOnly`
  /// rounds). Returns the slices used, or nothing when the solution is not usable.
  std::vector<char> solveRound(const std::vector<ContourPiercing>& counted, const std::vector<char>& free,
                               bool translationOnly) {
    const std::size_t n = n_;
    PoseCorrection& out = out_;
    ceres::CauchyLoss loss(out.robust_scale_mm / out.noise_mm);  // one for every piercing
    ceres::Problem::Options po;
    po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    for (std::size_t i = 0; i < n; ++i) w_[i] = t_[i] = {0, 0, 0};
    std::vector<char> used(n, 0);
    const auto block = [&](std::size_t i) {
      if (!used[i]) {
        used[i] = 1;
        problem.AddParameterBlock(w_[i].data(), 3);
        problem.AddParameterBlock(t_[i].data(), 3);
      }
    };
    for (const ContourPiercing& m : counted) block(std::size_t(m.from)), block(std::size_t(m.to));
    for (const auto& [i, j] : ties_) block(i), block(j);
    for (const ContourPiercing& m : counted) {
      const std::size_t a = std::size_t(m.from), b = std::size_t(m.to);
      auto* cost = new PiercingCost(m, {out.slices[a].pivot + T_[a], out.slices[b].pivot + T_[b]}, 1.0 / out.noise_mm);
      problem.AddResidualBlock(cost, &loss, w_[a].data(), t_[a].data(), w_[b].data(), t_[b].data());
    }
    for (const auto& [i, j] : ties_) {
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<TieCost, 6, 3, 3, 3, 3>(new TieCost{
                                   rotationVector(R_[i]) - rotationVector(R_[j]), T_[i] - T_[j],
                                   1.0 / (tieScale_ * sigmaRad_), 1.0 / (tieScale_ * out.sigma_mm)}),
                               nullptr, w_[i].data(), t_[i].data(), w_[j].data(), t_[j].data());
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (!used[i]) continue;
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PriorCost, 6, 3, 3>(new PriorCost{
                                   rotationVector(R_[i]), T_[i], 1.0 / sigmaRad_, 1.0 / out.sigma_mm}),
                               nullptr, w_[i].data(), t_[i].data());
      if (translationOnly || !free[i]) problem.SetParameterBlockConstant(w_[i].data());
      if (!free[i]) problem.SetParameterBlockConstant(t_[i].data());
    }
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    std::string why;
    if (!so.IsValid(&why)) so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    so.num_threads = 1;
    so.max_num_iterations = 50;
    so.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    if (!summary.IsSolutionUsable()) return {};
    return used;
  }

  /// Per slice: the information its own crossings give at the solution (weighted as the fit weighs
  /// them) and its ties', and the spread of the piercing distances.
  struct Information {
    std::vector<Eigen::Matrix<double, 6, 6>> data, ties;
    double spread = 0;
  };
  Information information() const {
    const std::size_t n = n_;
    const PoseCorrection& out = out_;
    const std::vector<ContourPiercing> observations = contourPiercings(planes_, commonRegions(recordedPairs_, planes_), cp_);
    const GapStats solved = gapStats(observations, n);
    Information result;
    result.spread = solved.all.empty() ? out.noise_mm : std::max(out.noise_mm, 1.4826 * upperMedian(absolute(solved.all)));
    const double scale = std::max(3 * result.spread, 3 * out.noise_mm);
    ceres::CauchyLoss loss(scale);
    std::vector<Eigen::Matrix<double, 6, 6>>& info = result.data;
    info.assign(n, Eigen::Matrix<double, 6, 6>::Zero());
    for (const ContourPiercing& m : observations) {
      const std::size_t a = std::size_t(m.from), b = std::size_t(m.to);
      const double zero[3] = {0, 0, 0};
      double r = 0;
      Eigen::Matrix<double, 1, 12> j;
      if (!piercingResidual(m, {out.slices[a].pivot + T_[a], out.slices[b].pivot + T_[b]}, 1.0, zero, zero, zero, zero, &r,
                            &j))
        continue;
      const double *j0 = j.data(), *j1 = j.data() + 3, *j2 = j.data() + 6, *j3 = j.data() + 9;
      double rho[3];
      loss.Evaluate(r * r, rho);
      // Weighted as the fit weighs it (1 / noise²), so that the observability test judges the
      // information the fit actually drew from the data; robust weight in 1 / mm².
      const double weight = rho[1] / (out.noise_mm * out.noise_mm);
      for (const auto& [slice, jw, jt] : {std::tuple{a, j0, j1}, std::tuple{b, j2, j3}}) {
        const Plane& pl = input_[slice].plane;
        Eigen::Matrix3d frame;
        frame << pl.u, pl.v, pl.normal;
        Eigen::Matrix<double, 1, 6> row;
        row.head<3>() = Eigen::RowVector3d(jw[0], jw[1], jw[2]) * frame;
        row.tail<3>() = Eigen::RowVector3d(jt[0], jt[1], jt[2]) * frame;
        info[slice] += weight * row.transpose() * row;
      }
    }
    // A sweep's tie constrains both frames it joins (its own-block information).
    result.ties.assign(n, Eigen::Matrix<double, 6, 6>::Zero());
    for (const auto& [i, j] : ties_)
      for (const std::size_t k : {i, j})
        for (int d = 0; d < 6; ++d)
          result.ties[k](d, d) += 1.0 / std::pow(tieScale_ * (d < 3 ? sigmaRad_ : out.sigma_mm), 2);
    return result;
  }

  /// Slice i's correction in its own frame, less the directions its crossings do not observe (named
  /// in c.unobservable), and its uncertainty.
  void correctSlice(std::size_t i, const Information& info) {
    PoseCorrection& out = out_;
    const bool rigid = rigid_;
    const int dof = rigid ? 6 : 3;
    const double sigmaRad = sigmaRad_;
    const Eigen::Matrix<double, 6, 1> priorScale =
        (Eigen::Matrix<double, 6, 1>() << sigmaRad, sigmaRad, sigmaRad, out.sigma_mm, out.sigma_mm, out.sigma_mm)
            .finished();
    SliceCorrection& c = out.slices[i];
    const Plane& rec = input_[i].plane;
    Eigen::Matrix3d frame;
    frame << rec.u, rec.v, rec.normal;
    // The correction in the slice's frame, scaled by the prior: [rotation; translation].
    Eigen::Matrix<double, 6, 1> local;
    local.head<3>() = frame.transpose() * rotationVector(R_[i]);
    local.tail<3>() = frame.transpose() * T_[i];
    const int first6 = rigid ? 0 : 3;
    const Eigen::MatrixXd Hdata = info.data[i].block(first6, first6, dof, dof);
    const Eigen::MatrixXd Hties = info.ties[i].block(first6, first6, dof, dof);
    const Eigen::MatrixXd H = Hdata + Hties;
    const Eigen::VectorXd s = priorScale.segment(first6, dof);
    const Eigen::MatrixXd scaled = s.asDiagonal() * H * s.asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scaled);
    Eigen::VectorXd x = s.cwiseInverse().asDiagonal() * local.segment(first6, dof);
    for (int k = 0; k < dof; ++k) {
      if (eig.eigenvalues()[k] >= kObservable) continue;
      const Eigen::VectorXd v = eig.eigenvectors().col(k);
      x -= v * v.dot(x);
      // Name it by its larger part (rotation or translation).
      const Eigen::VectorXd dir = s.asDiagonal() * v;
      const bool isRotation = rigid && dir.head<3>().norm() / sigmaRad_ > dir.tail<3>().norm() / out.sigma_mm;
      const Vec3 part = isRotation ? Vec3(v.head<3>()) : Vec3(v.tail<3>());
      c.unobservable.push_back(isRotation ? directionName("rotation", "about", part.normalized())
                                          : directionName("translation", "along", part.normalized()));
    }
    local.segment(first6, dof) = s.asDiagonal() * x;
    if (!rigid) local.head<3>().setZero();
    c.rotation = frame * local.head<3>();
    c.translation = frame * local.tail<3>();
    c.shift_mm = c.translation.norm();
    c.rotation_deg = c.rotation.norm() / kDeg;
    // Uncertainty: (JᵀJ / s² + prior)^-1 with s the distances' spread (H carries 1 / noise²).
    Eigen::MatrixXd A = Hdata * std::pow(out.noise_mm / info.spread, 2) + Hties;
    for (int k = 0; k < dof; ++k) A(k, k) += 1.0 / (s[k] * s[k]);
    const Eigen::MatrixXd cov = A.inverse();
    if (rigid) {
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> rot(cov.topLeftCorner(3, 3));
      c.sigma_rotation_deg = std::sqrt(std::max(0.0, rot.eigenvalues()[2])) / kDeg;
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> tr(cov.bottomRightCorner(3, 3));
    c.sigma_shift_mm = std::sqrt(std::max(0.0, tr.eigenvalues()[2]));
    if (!c.unobservable.empty()) ++out.slices_with_unobservable;
    out.planes[i] = correctedPlane(rec, c);
  }

  /// The piercing distances on the corrected poses (unobservable parts removed).
  void measureAfter() {
    const std::size_t n = n_;
    PoseCorrection& out = out_;
    std::vector<CuttingPlane> planes = input_;
    for (std::size_t i = 0; i < n; ++i) planes[i].plane = out.planes[i];
    const std::vector<ContourPiercing> observations = contourPiercings(planes, commonRegions(recordedPairs_, planes), cp_);
    const GapStats after = gapStats(observations, n);
    out.crossings_after = int(observations.size());
    out.gap_after_mm = rms(after.all);
    out.median_gap_after_mm = after.all.empty() ? 0.0 : upperMedian(absolute(after.all));
    for (std::size_t i = 0; i < n; ++i) {
      SliceCorrection& c = out.slices[i];
      c.crossings_after = int(after.per_slice[i].size());
      c.gap_after_mm = rms(after.per_slice[i]);
      out.outliers += c.outlier;
    }
  }

  const std::vector<char>& outliers() const { return outlier_; }

 private:
  const std::vector<CuttingPlane>& input_;
  const std::vector<PlanePairTraces>& recordedPairs_;
  const PoseCorrectionParams& params_;
  PoseCorrection& out_;
  const std::size_t n_;
  const bool rigid_;
  std::vector<CuttingPlane> planes_;  ///< the current poses
  std::vector<Eigen::Matrix3d> R_;    ///< the corrections so far: rotation about the pivot
  std::vector<Vec3> T_;               ///< and translation
  std::vector<std::array<double, 3>> w_, t_;  ///< one round's correction (Ceres' parameter blocks)
  double radius_ = 0, lever_ = 0, sigmaRad_ = 0, tieScale_ = 1;
  /// A slice findStranded sent back to its recorded pose, with where the first stage had left it.
  struct StrandedSlice {
    std::size_t index;
    CuttingPlane plane;
    Eigen::Matrix3d R;
    Vec3 T;
    double rms;  ///< its piercings' RMS distance there, mm (infinity: none)
  };
  std::vector<StrandedSlice> stranded_;
  /// The recorded poses' piercings at the automatic gate (piercingSpread), for round 0.
  std::vector<ContourPiercing> recordedPiercings_;
  PiercingParams cp_;
  std::vector<std::pair<std::size_t, std::size_t>> ties_;
  std::vector<char> outlier_;
  bool anyOutlier_ = false;
};

PoseCorrection correctPoses(const std::vector<CuttingPlane>& input, const std::vector<PlanePairTraces>& recordedPairs,
                            const PoseCorrectionParams& params) {
  const std::size_t n = input.size();
  PoseCorrection out;
  out.slices.resize(n);
  for (const CuttingPlane& p : input) out.planes.push_back(p.plane);
  if (params.kind == PoseCorrectionKind::none || n < 2) {
    out.converged = true;  // nothing to estimate
    return out;
  }
  PoseFit fit(input, recordedPairs, params, out);
  if (!fit.measureScales()) {
    out.converged = true;
    return out;
  }
  fit.setScalesAndTies();
  fit.findOutliers();
  out.converged = fit.fitStages();
  for (std::size_t i = 0; i < n; ++i) out.slices[i].outlier = fit.outliers()[i];
  const PoseFit::Information info = fit.information();
  for (std::size_t i = 0; i < n; ++i) fit.correctSlice(i, info);
  fit.measureAfter();
  return out;
}

}  // namespace xsect
