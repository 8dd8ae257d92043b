// Methods 1 and 2 sampled on the grid (see sampled_methods.h).
#include "pipeline/methods/sampled_methods.h"

#include "geometry/meshing/volume_mesher.h"
#include "io/input_error.h"
#include "pipeline/mesh_bounds.h"
#include "pipeline/reconstruct_stage.h"
#include "pipeline/run_outputs.h"

namespace xsect {

ReconstructStage SampledMethod::reconstruct(const RunInputs& in, const SceneStage& built, const ArrangeStage&,
                                            Progress& progress) const {
  const RunConfig& c = in.config;
  ReconstructStage r;
  // The unrepaired set is read only by the smoothing (smooth_stage.cpp).
  r.solid = reconstructOnGrid(built.scene, progress.counter(), c.smoothing_method != SmoothingMethod::none);
  if (r.solid.voxels_inside == 0) {
    // A voxel so coarse that nothing is left: the configuration must change (exit 2, issue 48: an
    // explicit size as an automatic one), and the message says to what.
    const VoxelSizeReport& v = built.voxel_size;
    const bool budget = v.automatic && v.choice.limited_by == VoxelSizeLimit::voxel_budget;
    throw InputError(c.path, budget ? "reconstruction.voxel_budget" : "reconstruction.voxel_size_mm",
                     emptySolidMessage(v, built.counts.sections));
  }
  return r;
}

MethodMesh SampledMethod::mesh(const RunConfig& c, const SectionScene& scene, const ReconstructStage& solid,
                               bool) const {
  MethodMesh m;
  m.mesh = meshZeroLevel(solid.solid.field);
  if (c.conformal_mesh) m.cut = cutAlongSections(m.mesh, scene.planes, scene.fields, scene.params.voxel_mm);
  return m;
}

void SampledMethod::requireMeshBoundsSolid(const MeshTopology& mesh, const ReconstructStage& solid,
                                           const std::string& what) const {
  xsect::requireMeshBoundsSolid(mesh, solid.solid.voxel_betti, what);
}

void SampledMethod::addToReport(const RunResults& r, nlohmann::ordered_json& report) const {
  report["throughput"][evaluateKey()] = r.reconstruction.solid.evaluate_seconds;
}

ReconstructStage SectionVoronoiMethod::reconstruct(const RunInputs& in, const SceneStage& built,
                                                   const ArrangeStage& arrangement, Progress& progress) const {
  ReconstructStage r = SampledMethod::reconstruct(in, built, arrangement, progress);
  // R'_Ω differs from R' where lifts were not followed and where method 1's voxels on the pieces
  // were added: counted as it evaluated (zero when every piece is whole).
  r.voxels_decided_by_pieces = r.solid.observed_lift_voxels_dropped + r.solid.observed_pieces_voxels_added;
  return r;
}

void SectionVoronoiMethod::addToReport(const RunResults& r, nlohmann::ordered_json& report) const {
  SampledMethod::addToReport(r, report);
  const SampledReconstruction& rec = r.reconstruction.solid;
  if (r.inputs.config.planes == PlaneExtent::observed)
    report["reconstruction"]["observed_pieces"] = {{"lift_voxels_kept", rec.observed_lift_voxels_kept},
                                                   {"lift_voxels_dropped", rec.observed_lift_voxels_dropped},
                                                   {"voxels_added_by_method_1", rec.observed_pieces_voxels_added}};
}

}  // namespace xsect
