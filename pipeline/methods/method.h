// The reconstruction methods of the thesis behind one interface (issue 50, item 3): method 1
// (`nearest_plane`, ch. 1 Def. 16), method 2 (`section_voronoi`, ch. 2 Def. 28) and method 3
// (`delaunay`, ch. 3 Def. 50). A method says which graph joins the sections in each cell (stage 4:
// G, G' or G''), reconstructs its solid on the scene's grid (stage 5), gives its own mesh and checks
// that the mesh bounds its solid (stage 7), and adds its own measurements to report.json. The
// run chooses one where the configuration names it (methodFor) and never asks which it runs.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "geometry/arrangement/connectivity_graph.h"
#include "geometry/arrangement/section_arrangement.h"
#include "geometry/meshing/conformal_cut.h"
#include "geometry/meshing/mesh_topology.h"
#include "io/run_config.h"

namespace xsect {

struct RunInputs;
struct SceneStage;
struct ArrangeStage;
struct ReconstructStage;
struct RunResults;
struct SectionScene;
class Progress;

/// What stage 4 builds for a method beside G (thesis ch. 1 §3).
struct MethodGraphs {
  bool g_prime = false;    ///< G' (ch. 2 §2, Def. 30): methods 2 and 3
  bool branching = false;  ///< the branching diagram of every cell's faces and G'' (Def. 44-45): method 3
};

/// A method's own mesh, unsmoothed: what mesh.<fmt> holds without smoothing, mesh_unsmoothed.<fmt>
/// with it.
struct MethodMesh {
  TriangleMesh mesh;
  ConformalCutStats cut;                   ///< the conformal cut along the sections, when asked
  bool conformal_by_construction = false;  ///< through the contours without a cut (method 3's ∂R'')
  std::vector<std::string> warnings;       ///< what the mesh is, where it is not what the method promises
};

class Method {
 public:
  virtual ~Method() = default;
  /// reconstruction.method's value.
  virtual ReconstructionMethod id() const = 0;
  /// Stage 4: the graphs it joins sections by.
  virtual MethodGraphs graphs() const = 0;
  /// Stage 4: throws InputError naming reconstruction.method when it cannot reconstruct from this
  /// arrangement of planes.
  virtual void requireArrangement(const RunConfig& config, const SectionArrangement& arrangement) const;
  /// What stage 5's progress counts ("blocks" of the grid, or "cells" of the arrangement).
  virtual const char* progressUnit() const;
  /// Stage 5: its solid on the scene's grid (ReconstructStage::solid, its warnings and its own
  /// results); the graph checks are the stage's (reconstruct_stage.h).
  virtual ReconstructStage reconstruct(const RunInputs& inputs, const SceneStage& scene,
                                       const ArrangeStage& arrangement, Progress& progress) const = 0;
  /// Stage 7: its mesh of `solid`; `smoothed`: the run smooths it (mesh.<fmt> is then the smooth surface).
  virtual MethodMesh mesh(const RunConfig& config, const SectionScene& scene, const ReconstructStage& solid,
                          bool smoothed) const = 0;
  /// Stage 7: throws std::runtime_error naming `what` unless `mesh` (the topology of its mesh)
  /// bounds its solid (pipeline/mesh_bounds.h).
  virtual void requireMeshBoundsSolid(const MeshTopology& mesh, const ReconstructStage& solid,
                                      const std::string& what) const = 0;
  /// The sampling conditions it is diagnosed by (geometry/sampling/sampling_conditions.h): its own,
  /// or, for a method without a sampling theorem, those of the method whose graph it contains.
  virtual ReconstructionMethod samplingConditions() const;
  /// The section pairs its solid joins per cell when it says them itself (graph.json
  /// `<method>_connections`); nullptr when its graph says them.
  virtual const std::vector<GraphEdge>* joinsRealised(const ReconstructStage& solid) const;
  /// report.json: its own keys, added to the report the run built (`reconstruction`, `conformity`,
  /// `throughput`).
  virtual void addToReport(const RunResults& results, nlohmann::ordered_json& report) const;
};

/// The method reconstruction.method names.
std::unique_ptr<const Method> methodFor(ReconstructionMethod method);

}  // namespace xsect
