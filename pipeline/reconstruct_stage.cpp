// Stage 5: the method's solid on the grid and its check against the graph (see reconstruct_stage.h).
#include "pipeline/reconstruct_stage.h"

namespace xsect {

ReconstructStage reconstructStage(const RunInputs& in, const SceneStage& built, const ArrangeStage& a,
                                  const Method& method, Progress& progress) {
  ReconstructStage r = method.reconstruct(in, built, a, progress);
  const SectionScene& scene = built.scene;
  r.graph_check = compareWithVoxels(a.methodEdges(), scene, a.arrangement, r.solid.inside);
  r.cell_check = compareCellsWithVoxels(a.methodEdges(), scene, a.arrangement, r.solid.inside);
  const GraphVoxelCheck& g = r.graph_check;
  if (!g.same_partition)
    r.warnings.push_back("the connectivity graph and the voxel solid group the sections differently (" +
                         std::to_string(g.pairs_joined_by_graph_only) + " pairs joined by the graph only, " +
                         std::to_string(g.pairs_joined_by_voxels_only) + " by the voxels only, " +
                         std::to_string(g.sections_unlocated) + " sections not located)");
  return r;
}

}  // namespace xsect
