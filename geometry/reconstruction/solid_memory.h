// Memory a reconstruction will keep, estimated before it runs (issue 17, item 4): the solid is
// stored by blocks of 8³ voxels (block_grid.h), so its memory is a table entry per block plus a
// leaf per block the values vary in: the blocks the boundary passes through (field, voxel sets,
// labels and the mesh made there), the blocks holding voxels of the solid (their deciding planes,
// the per-cell check's components) and the blocks next to a plane (the repair's evidence).
// Those counts are measured on a coarse trial (method 1 on a grid of at most ~2 M voxels, same
// planes and end margin) and scaled to the real grid: by the area ratio (f², f = coarse voxel /
// voxel) for the boundary and the planes' neighbourhoods, by the volume ratio (f³) for the
// solid's interior. The mesh is counted at its upper bound per boundary block (2 triangles per
// voxel; measured on the freehand-2000 sweep: 1.6), the repair's runs per row of voxels. Stages
// that still hold whole volumes (the smoothing, several materials) add their bytes per voxel.
// Not counted: the planes, their rasters and the arrangement, which the run holds before this
// estimate is needed (freehand-2000: 721 MB of its 1.37 GB peak) and measures per stage.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/core/types.h"
#include "geometry/scene/section_scene.h"

namespace xsect {

struct SolidMemoryEstimate {
  std::int64_t voxels = 0;
  std::int64_t blocks = 0;              ///< blocks of 8³ voxels of the grid
  double coarse_factor = 1;             ///< the trial's voxel size over the grid's
  std::int64_t boundary_blocks = 0;     ///< estimated blocks the boundary passes through
  std::int64_t solid_blocks = 0;        ///< estimated blocks holding voxels of the solid
  std::int64_t plane_blocks = 0;        ///< estimated blocks next to a plane
  double table_bytes = 0;               ///< per-block tables of every block grid
  double leaf_bytes = 0;                ///< the leaves
  double mesh_bytes = 0;                ///< the meshes (method's, conformal cut), upper bound
  double dense_bytes = 0;               ///< stages still on whole volumes (dense_bytes_per_voxel)
  double total() const { return table_bytes + leaf_bytes + mesh_bytes + dense_bytes; }
};

/// Bytes per voxel of the smoothing stages (dense fields and voxel sets on the grid).
constexpr double kSmoothingBytesPerVoxel = 16;

/// The most the solid and meshes can keep on a grid of `blocks` blocks and `rows` rows of voxels
/// (dims[1] dims[2]): every block a leaf of every kind.
double worstCaseSolidBytes(double blocks, double rows);

/// @param real_planes            the planes with their sections (the end planes are added).
/// @param params                 the run's reconstruction parameters (voxel size, end margin).
/// @param dense_bytes_per_voxel  bytes per voxel of the stages that hold whole volumes (0 without
///                               smoothing and with one material).
/// Throws std::invalid_argument as reconstructionLayout.
SolidMemoryEstimate estimateSolidMemory(const std::vector<CuttingPlane>& real_planes,
                                        const ReconstructionParams& params, double dense_bytes_per_voxel);

}  // namespace xsect
