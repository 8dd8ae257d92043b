// Stage 5 of `xsect run` (docs/methods.md): the run's method reconstructs its solid on the scene's grid
// (pipeline/methods/: methods 1 and 2 sampled and repaired, method 3's R'' with its tetrahedra
// sampled), and the solid's components are checked against the method's connectivity graph from
// stage 4, globally and cell by cell (the thesis: R_C's components are the classes of S_C that the
// lifts join).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "geometry/arrangement/cell_connectivity_check.h"
#include "geometry/delaunay/delaunay_reconstruction.h"
#include "geometry/delaunay/tetrahedra_voxels.h"
#include "geometry/reconstruction/sampled_reconstruction.h"
#include "geometry/reconstruction/topology_control.h"
#include "pipeline/arrange_stage.h"
#include "pipeline/input_stage.h"
#include "pipeline/methods/method.h"
#include "pipeline/progress.h"
#include "pipeline/scene_stage.h"

namespace xsect {

/// Method 3: R'' itself (its boundary mesh, conformal by construction, its tetrahedra, the section
/// pairs they join and the pruning's statistics), and what its solid and checks read.
struct DelaunayStage {
  DelaunayReconstruction result;
  int components = 0;                    ///< components of the tetrahedra's union
  std::int64_t opened_copies = 0;        ///< vertex copies the mesh's opened pinches added
  int connections_not_in_graph = 0;      ///< realised connections missing from G''
  int graph_edges_not_realised = 0;      ///< edges of G'' that no tetrahedron realises
  double delaunay_s = 0;                 ///< delaunayReconstruction, s
  double voxelise_s = 0;                 ///< sampling the tetrahedra on the grid, s
  /// The Betti numbers of the glued boundary of R'' (zeros when it has open edges), the voxel rule
  /// and refinement that matched them (tetrahedra_voxels.h: the solid is then on the refined grid),
  /// and whether none did, so that the solid is the voxels made well-composed
  /// (`voxels_added_well_composed` added), the mesh theirs.
  Betti boundary_betti{0, 0, 0};
  VoxelLikeness voxels;
  bool mesh_from_voxels = false;
  int voxels_added_well_composed = 0;
};

struct ReconstructStage {
  SampledReconstruction solid;       ///< the method's solid on the grid (method 3: R'' sampled)
  GraphVoxelCheck graph_check;       ///< the method's graph against the solid's components
  CellConnectivityCheck cell_check;  ///< the same, cell by cell
  std::optional<DelaunayStage> delaunay;  ///< method 3's own results (`solid` is its voxelisation)
  /// Voxels that the observed pieces decide, when the method counted them as it evaluated (method
  /// 2's R'_Ω); the smoothing's report measures them otherwise (smooth_stage.cpp).
  std::optional<std::int64_t> voxels_decided_by_pieces;
  /// reconstruction.topology other than free (issue 51): the joins cut or added so that `solid` has
  /// the topology asked for (topology_control.h); `solid` is the solid chosen.
  std::optional<TopologyControl> topology;
  std::vector<std::string> warnings;  ///< what the stage found worth a warning (report.json's warnings)

  /// With `topology`: the method's graph as the chosen solid realises it, less the joins cut and
  /// with those added (sorted); empty otherwise.
  std::vector<GraphEdge> joins_chosen;

  /// The method's graph as the solid realises it: `methodEdges`, or joins_chosen with `topology`.
  const std::vector<GraphEdge>& joins(const std::vector<GraphEdge>& methodEdges) const {
    return topology ? joins_chosen : methodEdges;
  }
};

/// Reads the scene (stage 4's input) and the method's graph (stage 4); warns (ReconstructStage::
/// warnings) when the graph and the solid group the sections differently. Throws what the method's
/// reconstruction throws: for methods 1 and 2 InputError naming the voxel size or budget when the
/// solid is empty; for method 3 InputError naming reconstruction.method when R'' has no
/// tetrahedron (no two planes' sections face each other in a cell), a warning when its
/// voxelisation is empty; with reconstruction.topology, InputError naming it when the goal is not
/// reached by cutting joins.
ReconstructStage reconstructStage(const RunInputs& inputs, const SceneStage& scene, const ArrangeStage& arrangement,
                                  const Method& method, Progress& progress);

}  // namespace xsect
