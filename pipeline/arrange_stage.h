// Stage 4 of `xsect run` (GUIDE.md): the arrangement of the scene's planes (the real cutting planes
// and the end planes), its cells and the sub-sections on their faces (thesis ch. 1 §1.2), and the
// connectivity graphs between the sections that the lifts induce: G (method 1, ch. 1 §3) and G'
// (method 2, ch. 2 §2, Def. 30). Reads the scene (pipeline/scene_stage.h); produces the cells and
// graphs that stage 5 checks its solid against and graph.json / graph.dot write.
#pragma once

#include <vector>

#include "geometry/arrangement/connectivity_graph.h"
#include "geometry/arrangement/section_arrangement.h"
#include "geometry/scene/section_scene.h"
#include "io/run_config.h"

namespace xsect {

struct ArrangeStage {
  SectionArrangement arrangement;
  ConnectivityGraphs graphs;
  bool method2 = false;                  ///< G' was built (method 2)
  bool g_in_g_prime = true;              ///< G ⊆ G' (thesis ch. 2 §2), when method 2
  /// The method's graph: G for method 1, G' for method 2.
  const std::vector<GraphEdge>& methodEdges() const { return method2 ? graphs.g_prime : graphs.g; }
};

ArrangeStage arrangeStage(const RunConfig& config, const SectionScene& scene);

}  // namespace xsect
