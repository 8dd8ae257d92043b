// report.html's frames (issue 21): a few slices' images with the contours segmented from them
// drawn over (the slice holding the largest sections, the slice that disagrees most with those it
// crosses, the flagged ones and pose correction's outliers), as inline PNG.
#pragma once

#include <cstddef>
#include <string>

#include "pipeline/input_stage.h"

namespace xsect {

/// The frames' HTML (<figure>s with data: PNG images); a line saying why there are none for inputs
/// without images (.csl, .contour).
/// @param max_side_px  images are shrunk so that their longer side is at most this, pixels.
/// @param max_frames   at most this many frames.
std::string frameOverlaysHtml(const RunInputs& in, int max_side_px = 380, std::size_t max_frames = 5);

}  // namespace xsect
