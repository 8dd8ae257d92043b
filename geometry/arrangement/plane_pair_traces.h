// The pairs of cutting planes whose observed regions meet, with both planes' section traces on
// their common line (thesis Introduction §3.1: conformity of the sections along P ∩ Q; docs/methods.md
// stage 3). The measurement half of the conform stage: what each pair disagrees on, in mm.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/arrangement/section_traces.h"
#include "geometry/core/types.h"

namespace xsect {

struct PlanePairTraces {
  int a = -1, b = -1;   ///< indices into the planes, a < b
  CommonLine line;      ///< P_a ∩ P_b, t in mm
  Trace common;         ///< where both planes were observed along the line
  Trace trace_a, trace_b;  ///< the sections of P_a, P_b on the line (whole line)
  TraceDisagreement disagreement;  ///< within `common`
};

struct PlanePairSearch {
  std::vector<PlanePairTraces> pairs;  ///< informative pairs, sorted by (a, b)
  int pairs_near_parallel = 0;   ///< observed regions meet, angle below min_angle_deg
  int pairs_without_sections = 0;  ///< common region non-empty, no section on it in either plane
  /// Those two kinds of pairs, with their lines and traces: not measured, but an edit of one
  /// plane must not change their traces either.
  std::vector<PlanePairTraces> unmeasured;
};

/// Every pair of non-virtual planes whose common line crosses both observed regions, at an angle
/// of at least min_angle_deg, and where at least one plane has a section on the common region.
/// @param min_angle_deg  pairs at a smaller angle are counted, not measured: at an angle θ a
///                       pose error of δ mm moves the common line by δ / sin θ, so nearly
///                       parallel planes' disagreement says little about either section.
/// @param keep_unmeasured  list the unmeasured pairs with their traces (what conformity
///                       enforcement must leave alone); false: only count them. A sweep's frames
///                       are nearly parallel pair after pair, and tracing them all is most of the
///                       search (issue 17).
/// @param progress       optional, called with the pairs examined so far and the n (n - 1) / 2
///                       pairs in all, after each plane's pairs, from several threads at once.
/// Deterministic; parallel over the planes.
PlanePairSearch planePairTraces(const std::vector<CuttingPlane>& planes, double min_angle_deg,
                                bool keep_unmeasured = true,
                                const std::function<void(std::int64_t, std::int64_t)>& progress = {});

/// The traces of `pairs` (their lines and common regions kept) re-read from `planes` (edited
/// sections), with their disagreement.
std::vector<PlanePairTraces> retrace(const std::vector<PlanePairTraces>& pairs,
                                     const std::vector<CuttingPlane>& planes);

/// The same pairs on moved planes (pose correction): their common lines and common regions
/// recomputed, their traces not read (left empty, disagreement zero). Pairs whose planes became
/// parallel or whose observed regions no longer meet are left out.
std::vector<PlanePairTraces> commonRegions(const std::vector<PlanePairTraces>& pairs,
                                           const std::vector<CuttingPlane>& planes);

}  // namespace xsect
