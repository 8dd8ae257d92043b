// Stage 5 (GUIDE.md) on a voxel grid, end to end: the sections' distance rasters, the virtual end
// planes that close open cells, the evaluation of R (method 1, nearest_plane_reconstruction.h) or
// R' (method 2, section_voronoi_reconstruction.h), and the repair that gives the sampled solid the
// topology of the continuous one (digital_topology.h). The field returned is negative exactly on
// the repaired voxels, ready for meshing.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "geometry/core/digital_topology.h"
#include "geometry/reconstruction/reconstruction_method.h"
#include "geometry/reconstruction/section_distance_field.h"
#include "geometry/core/types.h"

namespace xsect {

struct ReconstructionParams {
  ReconstructionMethod method = ReconstructionMethod::nearest_plane;
  double voxel_mm = 0.5;                ///< grid spacing, mm (> 0)
  std::optional<double> end_margin_mm;  ///< distance of the virtual end planes beyond the
                                        ///< sections' bounds, mm; empty = automatic (end_planes.h)
  double band_voxels = 3.0;             ///< distance rasters keep exact values within this band
  /// Method 2: half-thickness of the thickened planes in voxels (Fig. 2.6); √3/2 makes every
  /// 26-connected voxel path across a plane meet the slab.
  double slab_voxels = 0.8660254037844386;
};

struct SampledReconstruction {
  ScalarField field;                   ///< negative inside the repaired solid, |value| <= band
  std::vector<std::uint8_t> inside;    ///< repaired voxel set of R
  std::vector<CuttingPlane> end_planes;  ///< virtual planes added
  /// f_P rasters, one per plane: the real planes in input order, then the end planes (empty).
  std::vector<SectionDistanceField> fields;
  double end_margin_mm = 0;
  bool end_margin_auto = false;
  TopologyRepair repair;
  Betti voxel_betti{0, 0, 0};
  std::int64_t voxels_inside = 0;
  double evaluate_seconds = 0;         ///< time spent evaluating the method on the grid
  /// Unrepaired evaluation of the method (R or R'), one byte per voxel: the set the thesis'
  /// statements (Theorem 18) are about, before the sampled topology is repaired.
  std::vector<std::uint8_t> raw_inside;
  /// Method 2: for voxels of R', the plane (index into the real planes, or -1) of the section
  /// whose Voronoi cell holds the voxel; method 1: the nearest plane for voxels of R.
  std::vector<int> section_plane;
  /// Largest d(x, np'(x)) over the voxels of R' (method 2) or d(x, np(x)) over R (method 1), mm:
  /// the longest lift segment [a, lift(a)] realised (bounds the heights used by Theorem 20).
  double max_lift_mm = 0;
  std::int64_t exact_face_tests = 0;   ///< method 2 statistics
  std::int64_t search_restarts = 0;
};

/// The grid and end margin reconstructNearestPlane will use, without evaluating anything (for
/// `xsect check` and for memory estimates). Throws std::invalid_argument as below.
struct ReconstructionLayout {
  GridSpec grid;
  double end_margin_mm = 0;
  bool end_margin_auto = false;
  Vec3 sections_min = Vec3::Zero(), sections_max = Vec3::Zero();
};
ReconstructionLayout reconstructionLayout(const std::vector<CuttingPlane>& planes,
                                          const ReconstructionParams& params);

/// Bytes per voxel held at once during the reconstruction (field, nearest-plane data, voxel sets).
constexpr double kReconstructionBytesPerVoxel = 32;

/// @param planes  the real cutting planes with their sections (at least one section overall).
/// Throws std::invalid_argument when there is no section at all or the grid would be too large
/// (over 2^31 voxels).
SampledReconstruction reconstructOnGrid(const std::vector<CuttingPlane>& planes,
                                              const ReconstructionParams& params,
                                              const std::function<void(double)>& progress = {});

}  // namespace xsect
