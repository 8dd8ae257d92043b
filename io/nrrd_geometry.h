// The grid lines of xsect's NRRD headers, shared by its label and scalar volumes: sizes, space
// directions (the voxel edges along +x, +y, +z), space origin (the centre of voxel (0, 0, 0),
// NRRD's cell-centred convention) and units, in xsect's world frame written as LPS (see
// label_volume_file.h for why).
#pragma once

#include <string>

#include "geometry/core/types.h"

namespace xsect {

/// Shortest text that reads back to the same double ("0" for ±0).
std::string nrrdNumber(double v);

/// "space: ...", "sizes: ...", "space directions: ...", "kinds: ...", then `dataLines` (endian and
/// encoding, where xsect's volumes have always had them), "space origin: ...", "space units: ...".
std::string nrrdGridLines(const GridSpec& grid, const std::string& dataLines);

}  // namespace xsect
