// Several materials (thesis remark after Def. 17; ch. 3's closing remark for method 3): the labels
// the sections carry, and each label's sections on the run's planes. With segmentation labels
// (or a contour file with several materials) the planes hold the union of the labels and
// RunInputs::labelled each label's sections; otherwise the planes' own sections carry the labels.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/core/types.h"
#include "pipeline/input_stage.h"

namespace xsect {

/// Whether segmentation labels gave per-label sections (RunInputs::labelled).
bool anyLabelled(const RunInputs& in);

/// The labels the sections carry (segmentation labels when any plane has them), sorted.
std::vector<std::uint16_t> materialLabels(const RunInputs& in);

/// The run's planes (in.planes, same order) each holding only its sections of label `label`.
std::vector<CuttingPlane> materialPlanes(const RunInputs& in, std::uint16_t label);

}  // namespace xsect
