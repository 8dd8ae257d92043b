// Label volumes as NRRD files that 3D Slicer loads as label maps (docs/methods.md stage 8, "how users
// load results"): one unsigned 16-bit label per voxel of a GridSpec, gzip-compressed, with the
// grid's geometry in the header (sizes, space directions, space origin).
//
// Frame: xsect's world frame (the slices' frame, mm) is written as Slicer's LPS
// (`space: left-posterior-superior`), the convention Slicer assumes for files and the one xsect's
// meshes are read in; a label volume and a mesh of the same run therefore overlay in Slicer.
// The NRRD origin is the centre of voxel (0, 0, 0) (GridSpec::origin, NRRD's cell-centred
// convention), the space directions are the voxel edges (voxel size along x, y, z), and the data
// run with i fastest: index = i + dims[0] * (j + dims[1] * k), as GridSpec::index.
//
// The header also carries Slicer's segmentation metadata (SegmentN_* and Segmentation_* key/value
// pairs, one segment per non-zero label present): saved as NAME.seg.nrrd the file opens in Slicer
// as a segmentation whose segments are named "label L"; as NAME.nrrd it opens as a volume (tick
// "LabelMap" in Add Data, or name it NAME-label.nrrd). Other readers ignore these pairs.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct LabelVolume {
  GridSpec grid;                      ///< origin = centre of voxel (0,0,0), mm; voxel edge, mm
  std::vector<std::uint16_t> labels;  ///< grid.count() labels, 0 = background, i fastest
};

/// Writes `labels` on `grid` as a gzip-compressed NRRD (see the file comment). The bytes depend
/// only on the arguments (and the zlib build): writing twice gives the same file.
/// @param path    destination, e.g. "labels.seg.nrrd"; overwritten.
/// @param grid    dims all positive; voxel (edge length, mm) positive and finite; origin finite.
/// @param labels  grid.count() values, index = i + dims[0] * (j + dims[1] * k).
/// Throws std::invalid_argument on an invalid grid or a labels size that does not match it,
/// std::runtime_error if the file cannot be written.
void writeLabelVolumeNrrd(const std::string& path, const GridSpec& grid,
                          const std::vector<std::uint16_t>& labels);

/// Row (0 .. dims[0]-1, j, k) of a label volume into row[0 .. dims[0]-1]; called from several
/// threads at once.
using LabelRows = std::function<void(int j, int k, std::uint16_t* row)>;
/// The same, the labels given row by row (read twice: the header's segment extents, then the
/// data), so that no array of the whole volume is needed. The same bytes as the dense version.
void writeLabelVolumeNrrd(const std::string& path, const GridSpec& grid, const LabelRows& rows);

/// Reads a label volume written by writeLabelVolumeNrrd, or any attached-header NRRD of the same
/// kind: type unsigned short, dimension 3, encoding gzip or raw, little or big endian, space LPS,
/// space directions along +x, +y, +z with one positive voxel size, space origin.
/// Throws InputError(path, field, what) naming the NRRD field at fault: "magic", "header"
/// (no blank line ends it), a missing or malformed field ("type", "dimension", "sizes",
/// "encoding", "endian", "space", "space directions", "space origin", "space units",
/// "data file"), "sizes" when the data hold a different number of voxels, "data" for bad gzip
/// or truncated data.
LabelVolume readLabelVolumeNrrd(const std::string& path);

}  // namespace xsect
