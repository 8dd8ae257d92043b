// After stage 3 of `xsect run` (docs/methods.md), the scene every later stage reads, built once
// (geometry/scene/section_scene.h): the voxel size resolved (automatic_voxel_size.h) and checked
// against the sections' widths and this machine's memory, the grid and end margin, the six virtual
// end planes that close the arrangement's open cells (thesis ch. 1 §1.2), and each plane's f_P
// raster (ch. 1 §1.1).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "geometry/scene/section_scene.h"
#include "geometry/reconstruction/solid_memory.h"
#include "pipeline/input_stage.h"
#include "pipeline/time_budget.h"
#include "pipeline/voxel_size_choice.h"

namespace xsect {

struct SectionCounts {
  int sections = 0;             ///< sections on all planes
  int planes_with_sections = 0;
};

struct SceneStage {
  SectionCounts counts;
  VoxelSizeReport voxel_size;
  TimeEstimate time_estimate;  ///< the stages from the scene on (pipeline/time_budget.h)
  /// The memory estimate's coarse trial (solid_memory.h), when it was measured: the worst case did
  /// not fit, the grid is over 1e8 voxels, or it was asked for.
  std::optional<SolidMemoryEstimate> memory_trial;
  SectionScene scene;  ///< scene.params: the resolved settings (voxel size, method, end margin, planes)
  /// The scene's warnings (the end planes; a single plane holding sections); a too coarse voxel
  /// size's is voxel_size.warning.
  std::vector<std::string> warnings;
};

/// Reads the stage-3 planes; resolves the voxel size (the configuration stays as read: later
/// stages read the resolved settings from SceneStage::scene.params) and returns the scene with
/// its warnings. Throws InputError when no
/// plane holds a section, the grid would not fit in memory, or the run would take longer than
/// run.max_seconds with the `elapsed_s` already spent. `xsect check` and `xsect run` both build
/// their scene here, so that they refuse the same configurations; `want_memory_trial` (check)
/// keeps the memory estimate's trial in `memory_trial` whatever the grid.
SceneStage sceneStage(const RunInputs& in, bool quiet, double elapsed_s, bool want_memory_trial = false);

/// The warnings up to the scene, in the order a run reports them: a too coarse voxel size first,
/// then the inputs', then the scene's.
std::vector<std::string> warningsThroughScene(const RunInputs& in, const SceneStage& scene);

/// The estimate's parts in words, for messages.
std::string memoryBreakdown(const SolidMemoryEstimate& e);

/// report.json "reconstruction.voxel_size" and `xsect check`'s "voxel_size".
nlohmann::ordered_json voxelSizeJson(const VoxelSizeReport& r);

}  // namespace xsect
