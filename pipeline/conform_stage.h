// Stage 3 (GUIDE.md), conformity along plane intersections (thesis Introduction §3.1, ch. 2 §5):
// measures, for every pair of slices whose observed regions meet, how their sections' traces on
// the common line disagree; flags slices whose disagreement with the others is too large to be
// segmentation noise (probable tracking or segmentation failures) and optionally drops them;
// optionally enforces a consensus trace on every line (geometry/conformity/conformity_enforcement.h) and
// measures again. Its report goes to report.json (summary) and conformity.json (per pair and per
// slice).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "geometry/core/types.h"
#include "io/run_config.h"

namespace xsect {

struct ConformStage {
  std::vector<CuttingPlane> planes;              ///< dropped slices removed, sections edited
  std::vector<std::vector<Section>> labelled;    ///< per-label sections, rows kept in step
  nlohmann::ordered_json summary;                ///< report.json "conformity" (measurement part)
  nlohmann::ordered_json details;                ///< conformity.json
  std::vector<std::string> warnings;
  std::string stderr_summary;                    ///< one or two lines for the terminal
};

/// @param planes    the segmented slices (non-virtual cutting planes).
/// @param labelled  per plane, the sections of each label (may be empty: single material).
/// Slice numbers in the outputs are CuttingPlane::slice.
ConformStage conformStage(const RunConfig::Conformity& settings, std::vector<CuttingPlane> planes,
                          std::vector<std::vector<Section>> labelled);

}  // namespace xsect
