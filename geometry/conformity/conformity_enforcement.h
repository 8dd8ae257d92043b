// Enforced conformity along plane intersections (thesis Introduction §3.1 and ch. 2 §5 assume
// that the sections of two intersecting planes agree on their common line; docs/methods.md stage 3).
// For every pair of planes whose traces disagree, a consensus trace of their common line is
// chosen, and both planes' sections are edited so that their traces equal it:
//  - locally, and keeping the sections' topology where it can: an endpoint that only moves
//    (the consensus interval overlaps the current one) is moved by a bump, a smooth deformation
//    of the plane along the line within a disc around the endpoint (radius 2-4 times the move,
//    at most band_mm, clear of every other line and crossing); it maps the plane onto itself
//    diffeomorphically, so no section splits, merges or gains a hole;
//  - intervals that appear or vanish, and moves too near another line for a bump, are edited
//    with thin rhombi whose diagonal is the changed piece of the line (extended slightly into
//    the unchanged trace beside it), of half-width at most band_mm, added to or cut from the
//    sections with CGAL's exact Boolean operations, minus thin wedges around the plane's other
//    lines so that they keep their traces; sections no edit reaches are returned untouched;
//  - with shared vertices: the consensus endpoints become vertices of both planes' polygons,
//    the same world point;
//  - together: all lines through a plane are edited in one Boolean operation per round, and the
//    traces are re-read after every round; rounds repeat (at most max_rounds) while an edit of
//    one line has disturbed another (where two lines cross in a plane).
#pragma once

#include <vector>

#include "geometry/arrangement/plane_pair_traces.h"
#include "geometry/conformity/consensus_mode.h"
#include "geometry/core/types.h"

namespace xsect {

/// The consensus of two traces within the common region C (a subset of C).
Trace consensusTrace(const Trace& a, const Trace& b, const Trace& common, ConsensusMode mode);

struct ConformityParams {
  ConsensusMode mode = ConsensusMode::union_;
  /// A pair whose consensus would change either trace by a piece longer than this (mm) is left as
  /// it is and reported: such a disagreement is a tracking or segmentation failure, not noise.
  double max_correction_mm = 5.0;
  /// Edits stay within this distance of their line (mm; the rhombi's largest half-width).
  double band_mm = 2.0;
  /// Traces that disagree by at most this (symmetric difference, mm) already agree.
  double tolerance_mm = 1e-6;
  int max_rounds = 4;
};

struct PairCorrection {
  Trace consensus;          ///< the trace both planes were given (empty when not applied)
  double correction_a_mm = 0, correction_b_mm = 0;  ///< longest piece of (trace Δ consensus) ∩ C
  bool applied = false;     ///< both planes were edited to a consensus
  bool agrees = false;      ///< the traces agree (within tolerance_mm) at the end
  bool over_max = false;    ///< left as it was: a correction exceeded max_correction_mm
  bool not_editable = false;  ///< left as it was: a plane's sections are not simple polygons
};

struct ConformityEnforcement {
  std::vector<CuttingPlane> planes;         ///< the input planes with edited sections
  std::vector<PairCorrection> corrections;  ///< one per input pair, same order
  int rounds = 0;                           ///< rounds that edited something
  int planes_edited = 0;                    ///< planes whose sections changed
  int bumps = 0;                            ///< endpoint moves made by deforming the plane
  int rhombi_added = 0, rhombi_removed = 0; ///< Boolean edits applied (all rounds)
  int vertices_shared = 0;                  ///< consensus endpoints inserted as polygon vertices
  double max_half_width_mm = 0;             ///< widest edit: rhombus half-width or bump radius, mm
  std::vector<int> planes_not_editable;     ///< sections not simple polygons: left unedited
};

/// @param planes      the planes of `pairs` (indices), with their sections.
/// @param pairs       from planePairTraces on the same planes: the lines to make agree.
/// @param unmeasured  lines whose traces must not change (PlanePairSearch::unmeasured).
/// Deterministic whatever the thread count.
ConformityEnforcement enforceConformity(const std::vector<CuttingPlane>& planes,
                                        const std::vector<PlanePairTraces>& pairs,
                                        const ConformityParams& params,
                                        const std::vector<PlanePairTraces>& unmeasured = {});

}  // namespace xsect
