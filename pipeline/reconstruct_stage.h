// Stage 5 of `xsect run` (GUIDE.md): the voxel size resolved (geometry/reconstruction/
// automatic_voxel_size.h) and checked against this machine's memory, then method 1 (thesis ch. 1,
// Def. 16) or method 2 (ch. 2, Def. 28) sampled on the grid with the end planes that close the
// open cells and the sampled topology repaired (geometry/reconstruction/sampled_reconstruction.h).
// It runs before the arrangement (stage 4), which needs its end planes and distance rasters.
#pragma once

#include <nlohmann/json.hpp>

#include "geometry/reconstruction/sampled_reconstruction.h"
#include "pipeline/input_stage.h"
#include "pipeline/voxel_size_choice.h"

namespace xsect {

struct SectionCounts {
  int sections = 0;             ///< sections on all planes
  int planes_with_sections = 0;
};

struct ReconstructStage {
  SectionCounts counts;
  VoxelSizeReport voxel_size;
  ReconstructionParams params;
  SampledReconstruction solid;
};

/// Reads the stage-3 planes; appends its warnings (the end planes; a single plane holding
/// sections) to in.warnings and resolves in.config.voxel_size_mm. Throws InputError when no plane
/// holds a section, the grid would not fit in memory, or the solid is empty at a size the voxel
/// budget forced; std::runtime_error when it is empty at another size.
ReconstructStage reconstructStage(RunInputs& in, bool quiet, StageClock& clock, Progress& progress);

/// The voxel size for the run (auto resolved; a too coarse explicit size is a warning printed even
/// with --quiet), as `xsect check` also reports it.
VoxelSizeReport resolveVoxelSize(RunInputs& in, bool quiet);

/// The grid the reconstruction will use; configuration problems become InputError.
ReconstructionLayout layoutOf(const std::vector<CuttingPlane>& planes, const RunConfig& c);

/// report.json "reconstruction.voxel_size" and `xsect check`'s "voxel_size".
nlohmann::ordered_json voxelSizeJson(const VoxelSizeReport& r);

}  // namespace xsect
