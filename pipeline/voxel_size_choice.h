// The voxel size of a run (issue 14): `auto` resolved from the sections (automatic_voxel_size.h),
// and a check that the grid resolves them: when most sections are narrower than two voxels, an
// automatic size is an input error naming the size to use, an explicit one a loud warning.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "geometry/reconstruction/automatic_voxel_size.h"
#include "geometry/core/types.h"
#include "io/run_config.h"

namespace xsect {

struct VoxelSizeReport {
  double voxel_mm = 0;
  bool automatic = true;
  VoxelSizeChoice choice;               ///< the rule's terms (automatic sizes only)
  double median_section_width_mm = 0;   ///< inscribed-disk diameter (section_width.h)
  double min_section_width_mm = 0;
  int sections = 0;
  int sections_narrower_than_two_voxels = 0;
  double suggested_voxel_mm = 0;        ///< a quarter of the median section width
  std::string warning;                  ///< explicit size too coarse: what to do; else empty
};

/// The reconstruction's parameters from the configuration, at the voxel size `voxel_mm` (the
/// resolved one: VoxelSizeReport::voxel_mm, SectionScene::params).
ReconstructionParams reconstructionParams(const RunConfig& config, double voxel_mm);

/// Resolves the voxel size (the configuration's, or the automatic one when it is `auto`; the
/// configuration is not changed) and checks the grid against the
/// sections' widths, and the size against what OpenVDB and single-precision meshes can hold
/// (voxels of at least 2e-5 mm; coordinates within 2^19 voxels of the origin). Throws InputError (reconstruction.voxel_size_mm) when an automatic size
/// leaves most sections narrower than two voxels (only the voxel budget can force that).
/// @param planes  the real planes with their sections (at least one section).
VoxelSizeReport chooseVoxelSize(const RunConfig& config, const std::vector<CuttingPlane>& planes);

/// Bytes per voxel of the configured stages that still hold whole volumes (smoothing, several
/// materials with methods 1 and 2); 0 for a method alone.
double denseBytesPerVoxel(const RunConfig& c);

/// The message of a run whose solid came out empty from non-empty sections: the grid, the
/// sections' width and the voxel size to use.
std::string emptySolidMessage(const VoxelSizeReport& report, int sections);

}  // namespace xsect
