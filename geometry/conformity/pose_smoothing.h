// Smoothing the recorded pose trajectory of a tracked sweep (the conform stage, docs/methods.md stage 3;
// thesis Introduction §3.1 assumes sections that agree, and a tracker's per-frame jitter moves
// each section by its own small rigid error). A probe moves smoothly between frames a few hundredths
// of a millimetre apart; its tracker reports each pose with independent noise (optical trackers:
// about 0.1 mm, 0.1 degree). An interpolating reconstruction (method 1, Shepard) passes through
// every frame and so reproduces each frame's error; fitting the trajectory locally averages it.
//
// The algorithm, frame by frame in the order given (a tracked sweep's acquisition order): over the
// frames of the same sweep within half_window of frame i (fewer at the ends), a weighted
// least-squares polynomial of degree 2 in the frame offset d (a local quadratic regression,
// tricube weights (1 - (|d| / (half_window + 1))³)³) is fitted to
//  - the position of frame i's reference point (e.g. the centre of its observed region) carried by
//    each neighbour's pose: the same point of the probe's image, followed along the sweep, and
//  - the neighbours' rotations relative to frame i, as rotation vectors log(R_iᵀ R_j) (so(3),
//    well defined for the small relative rotations of neighbouring frames);
// its value at d = 0 gives the frame's smoothed reference point and rotation R_i exp(ω). The plane
// carries its sections rigidly: they keep their plane coordinates, and the origin is placed so
// that the reference point keeps its plane coordinates too. A polynomial of degree 2 reproduces
// constant speed and constant acceleration exactly (with at least 4 frames in the window; fewer
// use degree 1), so a smooth sweep is not biased while the noise variance falls by about the
// window's effective number of frames.
//
// Robustness (Cleveland's robust LOWESS): a tracker glitch would pull every fit within half_window
// of it. After the first fit each frame's residual (its correction: shift of the reference point
// plus the rotation angle times the reference points' median distance from the origin) gives it
// the bisquare weight (1 - (r / s)²)² with s = 6 median r, at least 0.5 mm (smaller corrections
// are tracker noise, never a glitch), and the fit is repeated twice with the weights
// multiplied in: a frame far off its neighbours' trajectory gets weight 0, stops pulling them, and
// is itself put back onto it.
//
// Sweeps: consecutive frames that turn by more than 5° or whose reference points jump by more
// than 10 times the median step start a new sweep; windows do not cross sweeps (several stacks or
// sweeps listed one after the other are smoothed each on its own). A run of at most 3 frames cut
// off on both sides, whose neighbours continue each other, is a glitch within the sweep, not a
// sweep: the robust passes deal with it.
//
// It assumes the frames are in acquisition order and that the true motion is smooth over the
// window; a real jerk within a window is smoothed too (the per-frame correction is reported, so
// that a large one can be seen).
#pragma once

#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct PoseSmoothing {
  std::vector<Plane> planes;        ///< the smoothed planes, in the order given
  std::vector<double> shift_mm;     ///< per frame: how far the reference point moved
  std::vector<double> rotation_deg; ///< per frame: the angle of the rotation applied
  std::vector<double> robustness;   ///< per frame: its bisquare weight in the last fit (0: outlier)
  int sweeps = 1;                   ///< sweeps found (windows do not cross them)
};

/// @param planes       the frames' planes (orthonormal, right-handed), in acquisition order.
/// @param reference    per frame, the point (plane coordinates, mm) whose trajectory is fitted.
/// @param half_window  frames on each side (>= 1); fewer than 3 frames in all: returned as given,
///                     as is a frame with fewer than 2 frames of non-zero weight in its window.
/// Throws std::invalid_argument when reference.size() != planes.size() or half_window < 1.
PoseSmoothing smoothPoseTrajectory(const std::vector<Plane>& planes, const std::vector<Vec2>& reference,
                                   int half_window);

}  // namespace xsect
