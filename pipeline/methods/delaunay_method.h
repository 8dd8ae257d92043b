// Method 3 behind the method interface (method.h; thesis ch. 3): R'', the pruned Delaunay
// triangulation of the section-vertices and the branching points (geometry/delaunay/), needs the
// planes in general position along the sections (ch. 3 §2.4) and joins sections by G'' (Def. 44).
// Its solid is its tetrahedra sampled on the grid by the rule whose voxels have the Betti numbers of
// its boundary (geometry/delaunay/tetrahedra_voxels.h); its mesh is ∂R'' itself, conformal to the
// contours by construction. Where ∂R'' could not be glued closed, or no voxel set on the grid has its
// topology, the solid is the voxels made well-composed and the mesh is theirs (one solid, issue 49).
// It has no sampling theorem: it is diagnosed with method 2's conditions (G' ⊆ G'', Proposition 10).
#pragma once

#include "pipeline/methods/method.h"

namespace xsect {

class DelaunayMethod final : public Method {
 public:
  ReconstructionMethod id() const override { return ReconstructionMethod::delaunay; }
  MethodGraphs graphs() const override { return {true, true}; }
  void requireArrangement(const RunConfig& config, const SectionArrangement& arrangement) const override;
  const char* progressUnit() const override { return "cells"; }
  ReconstructStage reconstruct(const RunInputs& inputs, const SceneStage& scene, const ArrangeStage& arrangement,
                               Progress& progress) const override;
  MethodMesh mesh(const RunConfig& config, const SectionScene& scene, const ReconstructStage& solid,
                  bool smoothed) const override;
  void requireMeshBoundsSolid(const MeshTopology& mesh, const ReconstructStage& solid,
                              const std::string& what) const override;
  ReconstructionMethod samplingConditions() const override { return ReconstructionMethod::section_voronoi; }
  const std::vector<GraphEdge>* joinsRealised(const ReconstructStage& solid) const override;
  void addToReport(const RunResults& results, nlohmann::ordered_json& report) const override;
};

}  // namespace xsect
