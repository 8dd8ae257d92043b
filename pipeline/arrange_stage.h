// Stage 4 of `xsect run` (GUIDE.md): the arrangement of the cutting planes and end planes, its
// cells and the sub-sections on their faces (thesis ch. 1 §1.2), the connectivity graphs G
// (method 1, ch. 1 §3) and G' (method 2, ch. 2 §2, Def. 30) between the sections, and the check
// of the method's graph against the components of the voxel solid, globally and cell by cell. It
// reads the end planes and the distance rasters the reconstruction (stage 5) made.
#pragma once

#include <string>
#include <vector>

#include "geometry/arrangement/cell_connectivity_check.h"
#include "geometry/arrangement/connectivity_graph.h"
#include "geometry/arrangement/section_arrangement.h"
#include "pipeline/reconstruct_stage.h"

namespace xsect {

struct ArrangeStage {
  std::vector<CuttingPlane> all_planes;  ///< the real planes, then the end planes
  SectionArrangement arrangement;
  ConnectivityGraphs graphs;
  bool method2 = false;                  ///< G' was built (method 2)
  bool g_in_g_prime = true;              ///< G ⊆ G' (thesis ch. 2 §2), when method 2
  GraphVoxelCheck graph_check;           ///< the method's graph against the solid's components
  CellConnectivityCheck cell_check;      ///< the same, cell by cell
  /// The method's graph: G for method 1, G' for method 2.
  const std::vector<GraphEdge>& methodEdges() const { return method2 ? graphs.g_prime : graphs.g; }
};

/// Reads the conformed planes (stage 3) and the reconstruction (stage 5); appends a warning when
/// the graph and the solid group the sections differently.
ArrangeStage arrangeStage(const RunConfig& config, const std::vector<CuttingPlane>& planes,
                          const ReconstructStage& reconstruction, std::vector<std::string>* warnings);

}  // namespace xsect
