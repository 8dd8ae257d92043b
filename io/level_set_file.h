// Narrow-band level sets as OpenVDB files (.vdb; docs/methods.md stage 8, `level_set.vdb`): one
// openvdb::FloatGrid of grid class "level set" holding signed distances in mm, negative inside,
// at the active voxels of the band; every other voxel is ±background (the band's half-width),
// negative where the surface encloses it (OpenVDB's signed flood fill), as level-set tools expect.
//
// Frame: xsect's world frame (the slices' frame, mm; the frame of its meshes and label volumes).
// The grid's transform is a uniform scale by the voxel edge followed by a translation to the centre
// of voxel (0, 0, 0): index (i, j, k) sits at grid.origin + grid.voxel * (i, j, k), as GridSpec.
// Grid metadata: "xsect_units" = "mm", "creator" = "xsect <version>", "xsect_frame" (a sentence)
// and "xsect_grid_dims" (Vec3i, GridSpec::dims, so that the sampled box survives a round trip).
// Compression: OpenVDB's active-mask compression only (OpenVDB never zips level sets; Blosc is
// left out because some OpenVDB builds, hence some readers, lack it).
//
// Loading it: Python `import pyopenvdb as vdb; g = vdb.read("level_set.vdb", "level_set")` (the
// module is `openvdb` in newer bindings); `g.transform.indexToWorld((i, j, k))` gives mm. Houdini and
// Blender (Volume object, "Import VDB" node) open it directly; ParaView and F3D through VTK's
// OpenVDB reader where the build has it. 3D Slicer has no built-in VDB reader: load the run's mesh
// or label volume there, or fill a volume node from Python (pyopenvdb copyToArray, then
// slicer.util.updateVolumeFromArray with origin/spacing from the transform; Slicer assumes LPS,
// the frame xsect's files are read in).
//
// Reproducible bytes: OpenVDB stamps every file with a random UUID (the 36-character text at bytes
// 21..56 of the header: magic 8, file version 4, library version 4+4, has-grid-offsets flag 1);
// writing the same grid twice gives files that differ in those bytes and nowhere else (checked
// with `cmp -l`; the tests also compare writes made with 1 and 4 TBB threads). The writer replaces it with a UUID-shaped
// tag derived from SHA-256 of the file with that field zeroed (version nibble 8, "custom", RFC
// 9562), so the bytes depend only on the level set, the grid name and the versions of xsect,
// OpenVDB and Blosc (OpenVDB Blosc-compresses its delayed-load metadata when it can), and
// identical contents carry identical tags (OpenVDB's File::isIdentical compares these tags;
// readers do not check them against the contents).
#pragma once

#include <string>

#include "geometry/core/types.h"

namespace xsect {

/// Writes `ls` as a single-grid OpenVDB file (see the file comment); the file is first written
/// under a temporary name in the same folder, then renamed onto `path`.
/// @param path      destination, e.g. "out/level_set.vdb"; overwritten.
/// @param ls        background > 0 and finite (mm); grid.voxel > 0 and finite (mm); grid.origin
///                  finite (mm); grid.dims >= 0; coords.size() == values.size(); values finite (mm);
///                  no coordinate repeated. The order of coords does not matter.
/// @param gridName  the grid's name in the file.
/// Throws std::invalid_argument on invalid input, std::runtime_error if the file cannot be written.
void writeLevelSetVdb(const std::string& path, const NarrowBandLevelSet& ls,
                      const std::string& gridName = "level_set");

/// Reads the float level-set grid `gridName` from a .vdb file.
/// - background: the grid's background (must be > 0 and finite).
/// - grid.origin, grid.voxel: from the transform, which must be linear, axis-aligned, with one
///   positive scale (the voxel edge, mm); other transforms are rejected.
/// - grid.dims and coords: from the "xsect_grid_dims" metadata when present (files written by
///   writeLevelSetVdb): coords are the grid's index coordinates, unchanged. Without it (files from
///   other tools), per axis: if the lowest active index m is negative, the origin moves to index m
///   and coords are shifted by -m (else origin and coords stay as in the file); dims = highest
///   (shifted) active index + 1. An empty grid without the metadata has dims (0, 0, 0).
/// - coords, values: every active voxel (active tiles expanded), sorted by (k, j, i).
/// A level set written by writeLevelSetVdb (coords sorted, as the struct requires) round-trips
/// exactly: grid, background, coords and values, bit for bit.
/// Throws InputError(path, field, what): "file" (missing, unreadable, not a VDB file, truncated or
/// corrupt, a format version other than 222..this OpenVDB's, a ZIP- or Blosc-compressed grid),
/// "grid" (no grid of that name, not a
/// float grid, too many active voxels), "grid class" (not a level set), "transform",
/// "background", "values" (non-finite), "xsect_grid_dims". Corrupt lengths and offsets are caught
/// before OpenVDB allocates for them; a corrupt byte inside the voxel data may go unnoticed
/// (VDB files carry no checksum).
NarrowBandLevelSet readLevelSetVdb(const std::string& path,
                                   const std::string& gridName = "level_set");

/// The level set's value at the voxel nearest to `worldPoint` (mm): the stored distance at an active
/// voxel, ±background elsewhere (negative inside the surface, after the writer's flood fill).
/// Reads and checks the grid as readLevelSetVdb does (same InputErrors); throws
/// std::invalid_argument if `worldPoint` is not finite.
float levelSetValueAt(const std::string& path, const Vec3& worldPoint,
                      const std::string& gridName = "level_set");

}  // namespace xsect
