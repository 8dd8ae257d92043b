// Stage 5: the solid on the scene's grid and its check against the graph (see reconstruct_stage.h).
#include "pipeline/reconstruct_stage.h"

#include <stdexcept>

#include "io/input_error.h"

namespace xsect {

ReconstructStage reconstructStage(const RunConfig& c, const SceneStage& built, const ArrangeStage& a,
                                  Progress& progress, std::vector<std::string>* warnings) {
  const SectionScene& scene = built.scene;
  ReconstructStage r;
  r.solid = reconstructOnGrid(scene, progress.counter());
  const SampledReconstruction& rec = r.solid;
  if (rec.voxels_inside == 0) {
    // An automatic size the budget forced so coarse that nothing is left: the configuration must
    // change (exit 2); otherwise exit 1 with the size to use (issue 14).
    const VoxelSizeReport& v = built.voxel_size;
    if (v.automatic && v.choice.limited_by == VoxelSizeLimit::voxel_budget)
      throw InputError(c.path, "reconstruction.voxel_budget", emptySolidMessage(v, built.counts.sections));
    throw std::runtime_error(emptySolidMessage(v, built.counts.sections));
  }
  r.graph_check = compareWithVoxels(a.methodEdges(), scene, a.arrangement, rec.inside);
  r.cell_check = compareCellsWithVoxels(a.methodEdges(), scene, a.arrangement, rec.inside);
  const GraphVoxelCheck& g = r.graph_check;
  if (!g.same_partition)
    warnings->push_back("the connectivity graph and the voxel solid group the sections differently (" +
                        std::to_string(g.pairs_joined_by_graph_only) + " pairs joined by the graph only, " +
                        std::to_string(g.pairs_joined_by_voxels_only) + " by the voxels only, " +
                        std::to_string(g.sections_unlocated) + " sections not located)");
  return r;
}

}  // namespace xsect
