// Methods 1 and 2 behind the method interface (method.h): the solid is the method sampled on the
// scene's grid, its sampled topology repaired (geometry/reconstruction/sampled_reconstruction.h);
// the mesh is its zero level, conformally cut along the sections when asked; report.json reads
// both from the repaired voxels. Method 1 (thesis ch. 1, Def. 16) joins sections by G; method 2
// (ch. 2, Def. 28) by G' (Def. 30), and counts as it evaluates the voxels that observed pieces
// decide (issue 20).
#pragma once

#include "pipeline/methods/method.h"

namespace xsect {

class SampledMethod : public Method {
 public:
  ReconstructStage reconstruct(const RunInputs& inputs, const SceneStage& scene, const ArrangeStage& arrangement,
                               Progress& progress) const override;
  MethodMesh mesh(const RunConfig& config, const SectionScene& scene, const ReconstructStage& solid,
                  bool smoothed) const override;
  void requireMeshBoundsSolid(const MeshTopology& mesh, const ReconstructStage& solid,
                              const std::string& what) const override;
  void addToReport(const RunResults& results, nlohmann::ordered_json& report) const override;

 protected:
  /// report.json throughput's key for its evaluation time.
  virtual const char* evaluateKey() const = 0;
};

/// Method 1: the nearest plane's section, lifted (thesis ch. 1, Def. 16).
class NearestPlaneMethod final : public SampledMethod {
 public:
  ReconstructionMethod id() const override { return ReconstructionMethod::nearest_plane; }
  MethodGraphs graphs() const override { return {}; }

 protected:
  const char* evaluateKey() const override { return "method1_evaluate_s"; }
};

/// Method 2: the section Voronoi lift (thesis ch. 2, Def. 28); on observed pieces R'_Ω.
class SectionVoronoiMethod final : public SampledMethod {
 public:
  ReconstructionMethod id() const override { return ReconstructionMethod::section_voronoi; }
  MethodGraphs graphs() const override { return {true, false}; }
  ReconstructStage reconstruct(const RunInputs& inputs, const SceneStage& scene, const ArrangeStage& arrangement,
                               Progress& progress) const override;
  void addToReport(const RunResults& results, nlohmann::ordered_json& report) const override;

 protected:
  const char* evaluateKey() const override { return "method2_evaluate_s"; }
};

}  // namespace xsect
