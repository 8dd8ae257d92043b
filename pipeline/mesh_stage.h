// Stage 7 of `xsect run` (GUIDE.md): the meshes and their check. The method's solid (or the smooth
// surface, stage 6) meshed and cut along the planes onto the section contours (conformal cut); per
// material, each voxel labelled with the section its lift comes from (thesis remark after Def. 17)
// and one mesh per label; then every mesh's topology (Betti numbers, watertight) required to be the
// one of the voxel solid it bounds (issue 14: a difference is a defect, exit 1, nothing written).
// Method 3 (thesis ch. 3) gives its mesh itself, ∂R'', conformal to the contours by construction
// (no marching, no cut), sampled on the grid by a rule whose voxels have its Betti numbers
// (reconstruct_stage.cpp, tetrahedra_voxels.h). Where no rule's voxels do, or ∂R'' could not be
// glued closed, the mesh is the voxels of R'' made well-composed, meshed and checked as methods 1 and 2
// do, with a warning and report.json reconstruction.delaunay.mesh_source "voxels": mesh.*,
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
  bool conformal_by_construction = false;  ///< `mesh` is method 3's ∂R'' (no cut applies)
  /// Method 3 whose glued boundary ∂R'' is not closed (open edges on the cutting planes): the
  /// method's mesh is then its voxelisation made well-composed and meshed as methods 1 and 2 do
  /// (conformally cut when asked), checked against `voxel_mesh_betti`, not ∂R'' itself.
  bool method3_from_voxels = false;
  Betti voxel_mesh_betti{0, 0, 0};      ///< of that well-composed voxel set
  int voxel_mesh_critical_added = 0;    ///< voxels added to make it well-composed
  BlockGrid<std::uint16_t> voxel_label;  ///< labels.nrrd
  /// Several materials: the labels changed so that each is well-composed (well_composed_labels.h).
  LabelComposition label_composition;
  std::vector<Material> materials;
  std::vector<std::string> warnings;  ///< labels without voxels, suspiciously many labels, method 3's boundary
};

/// @param smooth  stage 6's result, or nullptr without smoothing.
/// Warns (MeshStage::warnings) of labels without voxels, suspiciously many labels and method 3's
/// boundary where it could not be used.
MeshStage meshStage(const RunInputs& in, const SectionScene& scene, const ReconstructStage& reconstruction,
                    const SmoothStage* smooth);

struct DiagnoseStage {
  MeshTopology topology;         ///< of mesh.<fmt>
  MeshTopology method_topology;  ///< of the method's mesh (the same as `topology` without smoothing)
  std::vector<MeshTopology> material_topology;  ///< of each material's mesh, in MeshStage::materials' order
};

/// Every mesh's topology against its solid; throws std::runtime_error naming the mesh otherwise.
DiagnoseStage diagnoseStage(const ReconstructStage& reconstruction, const SmoothStage* smooth, const MeshStage& meshes);

}  // namespace xsect
