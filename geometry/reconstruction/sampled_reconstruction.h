// Stage 5 (docs/methods.md) on the scene's voxel grid (section_scene.h: the planes, the end planes that
// close open cells, the sections' distance rasters): the evaluation of R (method 1, nearest_plane_reconstruction.h) or
// R' (method 2, section_voronoi_reconstruction.h), and the repair that gives the sampled solid the
// topology of the continuous one (digital_topology.h). The field returned is negative exactly on
// the repaired voxels, ready for meshing.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "geometry/core/block_grid.h"
#include "geometry/core/digital_topology.h"
#include "geometry/scene/section_scene.h"
#include "geometry/core/types.h"

namespace xsect {

/// What the solid keeps, by blocks of 8³ voxels (block_grid.h): memory follows the leaves.
struct SolidStorage {
  std::int64_t blocks = 0;          ///< blocks of the grid (each has a table entry per block grid)
  std::int64_t field_leaves = 0;    ///< blocks the field varies in (the boundary passes through)
  std::int64_t section_leaves = 0;  ///< blocks holding voxels of R (their deciding planes)
  std::int64_t inside_leaves = 0;   ///< blocks of the repaired set holding both values
  std::int64_t anchor_leaves = 0;   ///< blocks of the repair's evidence holding both values
};

struct SampledReconstruction {
  /// Negative inside the repaired solid, |value| <= band; by blocks of 8³ voxels (block_grid.h):
  /// blocks where the method's value is clamped to one ±band throughout are tiles.
  BlockGrid<float> field;
  BlockGrid<std::uint8_t> inside;      ///< repaired voxel set of R (1 = in), by blocks
  TopologyRepair repair;
  Betti voxel_betti{0, 0, 0};
  std::int64_t voxels_inside = 0;
  double evaluate_seconds = 0;         ///< time spent evaluating the method on the grid
  /// Unrepaired evaluation of the method (R or R'), one byte per voxel: the set the thesis'
  /// statements (Theorem 18) are about, before the sampled topology is repaired. Kept only when
  /// asked (reconstructOnGrid's keep_raw_inside), empty otherwise: a copy of `inside` that only
  /// the smoothing of a solid decided by observed pieces reads (issue 17: the 4000-frame sweep).
  BlockGrid<std::uint8_t> raw_inside;
  /// Method 2: for voxels of R', the plane (index into the real planes, or -1) of the section
  /// whose Voronoi cell holds the voxel; method 1: the nearest plane for voxels of R. Blocks
  /// without a voxel of R are tiles of -1.
  BlockGrid<int> section_plane;
  /// Largest d(x, np'(x)) over the voxels of R' (method 2) or d(x, np(x)) over R (method 1), mm:
  /// the longest lift segment [a, lift(a)] realised (bounds the heights used by Theorem 20).
  double max_lift_mm = 0;
  SolidStorage storage;
  std::int64_t exact_face_tests = 0;   ///< method 2 statistics
  std::int64_t cells_clipped = 0;
  /// Method 2 on observed pieces (observed_section_voronoi.h): voxels of R' \ R_Ω kept (foot
  /// observed, ball observed or holding no other section) and dropped, and voxels of R_Ω \ R'
  /// added. Zero on whole planes.
  std::int64_t observed_lift_voxels_kept = 0;
  std::int64_t observed_lift_voxels_dropped = 0;
  std::int64_t observed_pieces_voxels_added = 0;
};

/// @param scene            the planes (real and end), their rasters and the grid (section_scene.h);
///                         the method is scene.params.method.
/// @param keep_raw_inside  also keep the unrepaired set (raw_inside).
SampledReconstruction reconstructOnGrid(const SectionScene& scene,
                                        const std::function<void(std::int64_t, std::int64_t)>& progress = {},
                                        bool keep_raw_inside = true);

}  // namespace xsect
