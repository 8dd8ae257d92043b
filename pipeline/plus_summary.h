// What `xsect check` and report.json say of a PLUS recording (issue 20): the frames read, kept
// and skipped, the frames the poses chain between, the pixel spacing and the sweep's extent.
#pragma once

#include <nlohmann/json.hpp>

#include "io/plus_sequence.h"

namespace xsect {

/// {frames, frames_used, skipped_image_not_ok, skipped_transform_not_ok, image_frame,
///  reference_frame, orientation, pixel_spacing_mm [first kept frame, along i and j],
///  field_of_view (a clip rectangle or fan), extent_mm [[min], [max]] of the kept frames' image
///  corners in the reference frame}.
nlohmann::ordered_json plusSequenceJson(const PlusSequence& s);

}  // namespace xsect
