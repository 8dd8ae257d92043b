// Stage 5 of `xsect run` (GUIDE.md): method 1 (thesis ch. 1, Def. 16) or method 2 (ch. 2, Def. 28)
// sampled on the scene's grid, its sampled topology repaired
// (geometry/reconstruction/sampled_reconstruction.h), and the solid's components checked against
// the method's connectivity graph from stage 4, globally and cell by cell (the thesis: R_C's
// components are the classes of S_C that the lifts join).
#pragma once

#include <string>
#include <vector>

#include "geometry/arrangement/cell_connectivity_check.h"
#include "geometry/reconstruction/sampled_reconstruction.h"
#include "pipeline/arrange_stage.h"
#include "pipeline/progress.h"
#include "pipeline/scene_stage.h"

namespace xsect {

struct ReconstructStage {
  SampledReconstruction solid;
  GraphVoxelCheck graph_check;       ///< the method's graph against the solid's components
  CellConnectivityCheck cell_check;  ///< the same, cell by cell
};

/// Reads the scene (stage 4's input) and the method's graph (stage 4); appends a warning when the
/// graph and the solid group the sections differently. Throws InputError when the solid is empty
/// at a size the voxel budget forced, std::runtime_error when it is empty at another size.
ReconstructStage reconstructStage(const RunConfig& config, const SceneStage& scene, const ArrangeStage& arrangement,
                                  Progress& progress, std::vector<std::string>* warnings);

}  // namespace xsect
