// Stage 7 of `xsect run` (docs/methods.md): the meshes and their check. The method's own mesh
// (pipeline/methods/: methods 1 and 2 mesh their solid and cut it along the planes onto the section
// contours; method 3 gives ∂R'' itself, conformal to the contours by construction, or its voxels'
// mesh where no voxel set has its topology) or the smooth surface (stage 6); per material, each
// voxel labelled with the section its lift comes from (thesis remark after Def. 17) and one mesh
// per label; then every mesh's topology (Betti numbers, watertight) required to be the one of the
// solid it bounds (issue 14: a difference is a defect, exit 1, nothing written): mesh.*,
// labels.nrrd and the Betti numbers always describe one solid (issue 49). With several materials,
// every method's materials are the label partition of the union's voxels. With smoothing,
// labels.nrrd is the smooth solid (one material).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "geometry/core/digital_topology.h"
#include "geometry/meshing/conformal_cut.h"
#include "geometry/meshing/mesh_topology.h"
#include "geometry/reconstruction/well_composed_labels.h"
#include "pipeline/reconstruct_stage.h"
#include "pipeline/smooth_stage.h"

namespace xsect {

/// One label's solid and mesh (written when there are at least two labels).
struct Material {
  std::uint16_t label = 0;
  TriangleMesh mesh;
  std::int64_t voxels = 0;
  Betti voxel_betti{0, 0, 0};
};

struct MeshStage {
  TriangleMesh method_mesh;         ///< with smoothing: the method's solid, conformally cut when
                                    ///< asked (empty without smoothing: `mesh` is that solid)
  TriangleMesh mesh;                ///< what mesh.<fmt> holds: the smooth surface, or the method's
  ConformalCutStats cut;            ///< of `mesh`
  bool conformal_by_construction = false;  ///< `mesh` is the method's, through the contours without a cut
  BlockGrid<std::uint16_t> voxel_label;  ///< labels.nrrd
  /// Several materials: the labels changed so that each is well-composed (well_composed_labels.h).
  LabelComposition label_composition;
  std::vector<Material> materials;
  std::vector<std::string> warnings;  ///< the method's mesh's (MethodMesh), labels without voxels, many labels
};

/// @param smooth  stage 6's result, or nullptr without smoothing.
/// Warns (MeshStage::warnings) of what the method's mesh is where it is not what the method
/// promises (method.h), labels without voxels and suspiciously many labels.
MeshStage meshStage(const RunInputs& in, const SectionScene& scene, const Method& method,
                    const ReconstructStage& reconstruction, const SmoothStage* smooth);

struct DiagnoseStage {
  MeshTopology topology;         ///< of mesh.<fmt>
  MeshTopology method_topology;  ///< of the method's mesh (the same as `topology` without smoothing)
  std::vector<MeshTopology> material_topology;  ///< of each material's mesh, in MeshStage::materials' order
};

/// Every mesh's topology against its solid; throws std::runtime_error naming the mesh otherwise.
DiagnoseStage diagnoseStage(const Method& method, const ReconstructStage& reconstruction, const SmoothStage* smooth,
                            const MeshStage& meshes);

}  // namespace xsect
