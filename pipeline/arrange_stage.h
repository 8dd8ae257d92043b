// Stage 4 of `xsect run` (docs/methods.md): the arrangement of the scene's planes (the real cutting planes
// and the end planes), its cells and the sub-sections on their faces (thesis ch. 1 §1.2), and the
// connectivity graphs between the sections that the lifts induce: G (method 1, ch. 1 §3), G'
// (methods 2 and 3, ch. 2 §2, Def. 30) and, for method 3, the branching diagram of every cell's
// faces with its points (ch. 2 §4, Def. 45) and G'' (Def. 44). Reads the scene
// (pipeline/scene_stage.h); produces the cells and graphs that stage 5 checks its solid against
// and graph.json / graph.dot write.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/arrangement/connectivity_graph.h"
#include "geometry/arrangement/section_arrangement.h"
#include "geometry/delaunay/delaunay_reconstruction.h"
#include "geometry/scene/section_scene.h"
#include "io/run_config.h"
#include "pipeline/methods/method.h"

namespace xsect {

struct ArrangeStage {
  SectionArrangement arrangement;
  ConnectivityGraphs graphs;
  bool with_g_prime = false;             ///< G' was built (methods 2 and 3)
  bool with_g_double_prime = false;      ///< G'' and the branching points were built (method 3)
  bool g_in_g_prime = true;              ///< G ⊆ G' (thesis ch. 2 §2, Proposition 5), when G' was built
  int g_not_in_g_prime = 0;              ///< edges of G missing from G' (same cell), when G' was built
  int g_prime_not_in_g_double_prime = 0; ///< edges of G' missing from G'' (same cell), method 3
  /// Method 3: the points added on the branching diagrams of the cells' faces (Def. 45), which
  /// delaunayReconstruction triangulates with the contour vertices.
  std::vector<BranchingPoint> branching;
  std::int64_t branching_rays = 0;       ///< method 3: (point, side) rays followed for the labeling Φ
  std::int64_t branching_labelled = 0;   ///< method 3: of them, with a label (branching_diagram.h)
  /// The method's graph: G for method 1, G' for method 2, G'' for method 3 (Def. 44; the
  /// connections R'' realises are reported beside it, reconstruct_stage.h).
  const std::vector<GraphEdge>& methodEdges() const {
    return with_g_double_prime ? graphs.g_double_prime : with_g_prime ? graphs.g_prime : graphs.g;
  }
};

/// The spacing of the section points of the arrangement, mm: the voxel size, coarser when the
/// sections' area would hold more than 250 000 points.
double arrangementSpacing(double voxel_mm, const std::vector<CuttingPlane>& planes, std::size_t realPlanes);

/// Builds what `method` joins sections by (Method::graphs); throws what Method::requireArrangement
/// throws for planes it cannot take.
ArrangeStage arrangeStage(const RunConfig& config, const SectionScene& scene, const Method& method);

/// How many edges of `sub` (sorted) are not in `super` (sorted), cell included.
int edgesMissing(const std::vector<GraphEdge>& sub, const std::vector<GraphEdge>& super);

}  // namespace xsect
