// Stage 6 (docs/methods.md, thesis ch. 1 §1.1): the smooth surface. Shepard's interpolant of the sections'
// distance functions evaluated on a grid, renormalised into an OpenVDB narrow-band level set and
// meshed; its connectivity between the sections compared with the method's graph (cell by cell,
// the cells the grid cannot decide re-decided on finer lattices: cell_refinement.h); and, when
// asked for or when Shepard joins the sections differently, a level-set smoothing of the method's
// solid that keeps the method's connectivity.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "geometry/arrangement/cell_connectivity_check.h"
#include "geometry/arrangement/cell_refinement.h"
#include "geometry/arrangement/connectivity_graph.h"
#include "geometry/smoothing/contour_pinning.h"
#include "geometry/core/digital_topology.h"
#include "geometry/reconstruction/sampled_reconstruction.h"
#include "geometry/arrangement/section_arrangement.h"
#include "geometry/meshing/volume_mesher.h"
#include "io/run_config.h"
#include "pipeline/arrange_stage.h"
#include "pipeline/reconstruct_stage.h"

namespace xsect {

struct SmoothStage {
  SmoothingMethod method = SmoothingMethod::none;  ///< what produced the surface: shepard | level_set
  LevelSetSurface surface;            ///< level set (level_set.vdb) and its mesh
  ScalarField field;                  ///< the dense field whose zero set it is (negative inside)
  double exponent = 1;                ///< Shepard's p
  double cap_mm = 0;                  ///< Shepard's clamp of f_i
  bool cap_auto = true;
  double empty_value_mm = 0;          ///< f_i of planes without sections (the end margin)
  double evaluate_s = 0;              ///< seconds evaluating Shepard's interpolant
  double mean_visible_planes = 0;     ///< planes seeing a voxel, on average
  int max_visible_planes = 0;
  std::vector<double> end_plane_weights;  ///< Shepard: the end planes' weight factors (-x +x -y +y -z +z)
  ContourPinning pinning;             ///< Shepard: the contours pinned on the grid
  GraphVoxelCheck shepard_check;      ///< Shepard's solid against the method's graph
  CellConnectivityCheck shepard_cells;  ///< the same, cell by cell
  /// Shepard: the cells its solid joined differently from the method's, re-decided on finer
  /// lattices (cell_refinement.h)
  std::vector<CellRefinement> refined_cells;
  bool shepard_keeps_connectivity = false;
  bool fell_back = false;             ///< Shepard's surface replaced by the level-set smoothing
  /// Voxels of the method's solid the observed pieces decide (Shepard asked for): how much the
  /// images' extent matters; Shepard's interpolant is then evaluated on the pieces.
  std::int64_t voxels_decided_by_pieces = 0;
  int iterations_applied = 0;         ///< level-set smoothing steps kept
  /// The smooth solid repaired as the method's is (digital_topology.h, plane_evidence.h): what
  /// the sections do not show removed, then well-composed, so that its mesh has its Betti numbers.
  TopologyRepair repair;
  Betti voxel_betti{0, 0, 0};         ///< of the smooth solid {field < 0}: the surface's, by construction
  bool adaptivity_dropped = false;    ///< the adaptive mesh changed the topology: meshed without
  GraphVoxelCheck final_check;        ///< the output's solid against the method's graph
  std::vector<std::string> warnings;  ///< shepardConnectivityWarning's, when it has one
  CellConnectivityCheck final_cells;  ///< the same, cell by cell
};

/// @param scene           the planes (real and end), their rasters and the grid (stage 4's input).
/// @param arrangement     stage 4: the cells and the method's graph (G for method 1, G' for method 2).
/// @param reconstruction  stage 5: the method's solid, and the graph against it (compareWithVoxels)
///                        which the level-set smoothing must keep unchanged, and the same cell by
///                        cell (compareCellsWithVoxels): Shepard keeps the method's connectivity
///                        when it joins the sections as the graph does overall and, in every cell
///                        both resolve, differs from the graph in no more section pairs than the
///                        method's own voxel solid does, on the grid or, where not, on the first
///                        finer lattice that resolves the cell (cell_refinement.h). The level-set
///                        smoothing stops before the first step that breaks either rule.
SmoothStage smoothStage(const RunConfig& config, const SectionScene& scene, const ArrangeStage& arrangement,
                        const ReconstructStage& reconstruction,
                        const std::function<void(std::int64_t, std::int64_t)>& progress = {});

/// The warning when Shepard's surface joins the sections differently from the method's graph
/// (what was measured, and what was written instead); empty otherwise.
std::string shepardConnectivityWarning(const RunConfig& config, const SmoothStage& smooth);

}  // namespace xsect
