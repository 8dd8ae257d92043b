// Scalar volumes as NRRD files (32-bit floats, gzip) on the same grid and frame as labels.nrrd
// (label_volume_file.h), for per-voxel diagnostics such as sampling.nrrd (issue 18): 3D Slicer
// loads them as scalar volumes that overlay the label map and the meshes.
#pragma once

#include <functional>
#include <string>

#include "geometry/core/types.h"

namespace xsect {

/// Row (0 .. dims[0]-1, j, k) of a scalar volume into row[0 .. dims[0]-1]; called from several
/// threads at once.
using ScalarRows = std::function<void(int j, int k, float* row)>;

/// @param description  one line written as a header comment (what the values are, their unit).
/// Throws std::invalid_argument on an invalid grid, std::runtime_error if the file cannot be
/// written. The bytes depend only on the arguments.
void writeScalarVolumeNrrd(const std::string& path, const GridSpec& grid, const ScalarRows& rows,
                           const std::string& description);

}  // namespace xsect
