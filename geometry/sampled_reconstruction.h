// Stage 5 (GUIDE.md), method 1 on a voxel grid, end to end: the sections' distance rasters, the
// virtual end planes that close open cells, the evaluation of R (nearest_plane_reconstruction.h),
// and the repair that gives the sampled solid the topology of R (digital_topology.h). The field
// returned is negative exactly on the repaired voxels, ready for meshing.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "geometry/digital_topology.h"
#include "geometry/section_distance_field.h"
#include "geometry/types.h"

namespace xsect {

struct ReconstructionParams {
  double voxel_mm = 0.5;                ///< grid spacing, mm (> 0)
  std::optional<double> end_margin_mm;  ///< distance of the virtual end planes beyond the
                                        ///< sections' bounds, mm; empty = automatic (end_planes.h)
  double band_voxels = 3.0;             ///< distance rasters keep exact values within this band
};

struct SampledReconstruction {
  ScalarField field;                   ///< negative inside the repaired solid, |value| <= band
  std::vector<std::uint8_t> inside;    ///< repaired voxel set of R
  std::vector<CuttingPlane> end_planes;  ///< virtual planes added
  std::vector<SectionDistanceField> fields;  ///< f_P rasters of the real planes, in input order
  double end_margin_mm = 0;
  bool end_margin_auto = false;
  TopologyRepair repair;
  Betti voxel_betti{0, 0, 0};
  std::int64_t voxels_inside = 0;
  double evaluate_seconds = 0;         ///< time spent evaluating method 1 on the grid
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
constexpr double kReconstructionBytesPerVoxel = 24;

/// @param planes  the real cutting planes with their sections (at least one section overall).
/// Throws std::invalid_argument when there is no section at all or the grid would be too large
/// (over 2^31 voxels).
SampledReconstruction reconstructNearestPlane(const std::vector<CuttingPlane>& planes,
                                              const ReconstructionParams& params,
                                              const std::function<void(double)>& progress = {});

}  // namespace xsect
