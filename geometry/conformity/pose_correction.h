// Pose correction (docs/methods.md stage 3; thesis Introduction §3.1 assumes that the sections of two
// intersecting planes agree on their common line): each slice's recorded pose is corrected by
// one rigid motion (or translation) so that, over all common lines, every point where a slice's
// contour crosses the line lies on the other slice's contours (geometry/conformity/
// contour_piercings.h: the piercing distance, measured in the other plane).
//
// The estimate, in rounds (the crossings and nearest contour points change as the poses move):
//  1. the pairs of slices whose observed regions met on the recorded poses, at an angle of at
//     least conformity.min_angle_deg, have their common lines and regions found again on the
//     current poses (commonRegions), and each contour crossing of either slice gives its piercing
//     distance in the other (left out beyond the gate, 3 sigma_mm + 4 noise, from every contour);
//  2. the corrections minimise
//        sum over piercings  rho((distance / noise)²)              (Cauchy loss, scale c)
//      + sum over slices   |omega|² / sigma_rad² + |tau|² / sigma_mm²   (the prior: corrections small)
//      [+ sum over consecutive frames of a sweep  |change|² / (sigma / half_window)²]
//     where a slice's correction turns it by the rotation vector omega about its pivot (the centre
//     of its sections) and moves the pivot by tau. The prior also fixes the gauge: a motion of all
//     slices together changes no distance, so the solution has none (no free global motion). The
//     robust scale c is 3 times the distances' robust spread (1.4826 × median) of the round, at
//     least 3 noise: it starts coarse (the recorded poses' spread) and narrows as the poses
//     converge, so that a slice far off (a tracker glitch) stops pulling its partners;
//  3. in rigid mode the first round solves translations only (coarse to fine);
//  4. outlier slices (a tracker glitch: the median of its pairs' largest endpoint mismatch above 3
//     times the typical slice's and the gate) are left out of the rounds above, then corrected in
//     rounds of their own against the others held fixed: they cannot drag their partners; so are
//     slices the rounds above left stranded (the median of their piercing distances above the
//     noise and 3 times the typical one, or a correction beyond 5 prior deviations), from their
//     recorded poses;
//  rounds repeat until the moves left are below noise / 10: a round's largest move of a point
//  within the median slice radius of its pivot, or the rest of the geometric decrease of the last
//  two rounds' moves when it halves at least (at most max_rounds per stage).
// Solved by Ceres (sparse normal Cholesky, one thread: deterministic), with the piercing residual's
// exact Jacobian (piercing_residual.h).
//
// Observability: per slice, the information its own piercings give about its 6 (or 3) motions
// (JᵀJ of its distances, robustly weighted, at the solution, in the slice's frame u, v, normal)
// is compared with the prior's; a direction where the data give less than 5% of the prior's
// information is unobservable: its correction is set to zero and reported (a slice crossing no
// other has all six). The uncertainty is the fit's: (JᵀJ / s² + prior)^-1 with s the final distances' spread,
// conditional on the other slices' poses (the largest standard deviation over directions).
//
// Units: noise is half the median pixel size (1e-3 of the sections' extent for contours given
// without pixels); sigma_mm, when not given, is the robust spread of the recorded piercing
// distances over √2 (at least noise; the piercings gated at 3 times the median pair's largest
// endpoint mismatch + 4 noise, which is also the fit's gate), and sigma_deg that over the larger of
// the sections' median radius and the slices' median half-diagonal (at most 10°): the data's own
// scale, in whatever units they come.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "geometry/arrangement/plane_pair_traces.h"
#include "geometry/conformity/pose_correction_kind.h"
#include "geometry/core/types.h"

namespace xsect {

struct PoseCorrectionParams {
  PoseCorrectionKind kind = PoseCorrectionKind::rigid;  ///< none: nothing is estimated
  std::optional<double> sigma_mm;    ///< prior std of a slice's translation, mm; empty = auto
  std::optional<double> sigma_deg;   ///< prior std of a slice's rotation, degrees; empty = auto
  /// > 0: consecutive frames (normals within 5°) are one sweep, whose corrections change by at
  /// most about sigma / sweep_half_window from frame to frame (conformity.pose_smoothing_frames).
  int sweep_half_window = 0;
  int max_rounds = 10;
};

/// One slice's correction: x -> pivot + R(rotation) (x - pivot) + translation (world, mm).
struct SliceCorrection {
  Vec3 pivot = Vec3::Zero();        ///< the centre of its sections on the recorded pose
  Vec3 rotation = Vec3::Zero();     ///< rotation vector, radians, world axes
  Vec3 translation = Vec3::Zero();  ///< of the pivot, mm
  double shift_mm = 0, rotation_deg = 0;              ///< |translation|, |rotation|
  double sigma_shift_mm = 0, sigma_rotation_deg = 0;  ///< the fit's largest 1-sigma
  /// Directions no crossing constrains, left at zero; in the slice's frame, e.g.
  /// "translation along normal", "rotation about u", or "translation along (0.6, 0, 0.8)".
  std::vector<std::string> unobservable;
  int crossings_before = 0, crossings_after = 0;      ///< piercings it takes part in (either side)
  double gap_before_mm = 0, gap_after_mm = 0;         ///< their RMS piercing distance
  /// Its disagreement set it apart (median over its pairs above 3 times the typical slice's and
  /// the gate): corrected against its partners held fixed, so that it cannot drag them.
  bool outlier = false;
  /// The correction as a 4x4 world transform (column vectors).
  Mat4 transform() const;
};

struct PoseCorrection {
  std::vector<Plane> planes;                ///< the corrected planes, input order
  std::vector<SliceCorrection> slices;      ///< input order
  double sigma_mm = 0, sigma_deg = 0;       ///< the priors used
  double noise_mm = 0, gate_mm = 0;         ///< measurement scale; piercing gate
  double robust_scale_mm = 0;               ///< the Cauchy scale of the last round
  int rounds = 0;
  bool converged = false;
  int crossings_before = 0, crossings_after = 0;           ///< piercings
  double gap_before_mm = 0, gap_after_mm = 0;              ///< RMS piercing distance
  double median_gap_before_mm = 0, median_gap_after_mm = 0;  ///< median |piercing distance|
  int outliers = 0;
  int slices_with_unobservable = 0;         ///< slices with at least one unobservable direction
};

/// The plane moved by a correction.
Plane correctedPlane(const Plane& recorded, const SliceCorrection& c);

/// @param planes          the slices (non-virtual), with sections and observed regions.
/// @param recorded_pairs  planePairTraces(planes, min_angle_deg, false).pairs: the pairs measured on
///                        the recorded poses (their disagreement gives the auto sigma and the
///                        outliers); later rounds follow the same pairs on the moved planes.
/// Deterministic whatever the thread count.
PoseCorrection correctPoses(const std::vector<CuttingPlane>& planes,
                            const std::vector<PlanePairTraces>& recorded_pairs, const PoseCorrectionParams& params);

}  // namespace xsect
