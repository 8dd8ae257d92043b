// The connectivity graphs between sections (thesis ch. 1 §1 and ch. 2 §2.1, Def. 30): in a cell C,
// sections A and B are joined when their lifts meet. Computed from the geometry along the lift
// segments [a, lift(a)] of the section points a of the arrangement (section_arrangement.h):
//  - G (method 1): lift(a) is where the ray from a, orthogonal to A's plane into C, first becomes
//    as near to another plane Q as to A's (exact, one root per plane); A and B are joined when the
//    projection of lift(a) on Q lies in a section B of Q (then lift(a) ∈ lift(A) ∩ lift(B)).
//  - G' (method 2): the ray is followed in steps of the sample spacing with the method-2 point
//    decision (section_voronoi_reconstruction.h); A and B are joined where the ray leaves A's lift
//    into the lift of a section B of another plane.
// A connection narrower than the sample spacing can be missed; both graphs are sampled on the same
// points, and G's edges are exact at those points.
// Observed pieces (issue 20, docs/methods.md, "Observed pieces"; the scene's pieces, when some is partial):
// method 1 on the pieces decides x by the nearest point of the union of the pieces, so G_Ω's lift
// of a ends at the first t where d(a + t n, Ω_Q) = t for another plane Q (a root of a
// non-increasing function, bracketed by the whole plane's root), and A joins the section B of Q
// holding the nearest point of Ω_Q. A lift may pass an unobserved part of a plane and meet B
// beyond the cell it starts in; the edge is listed in the cell where the lifts meet (the start
// cell when no section bounds that one). With whole pieces this is G.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/arrangement/section_arrangement.h"
#include "geometry/core/block_grid.h"
#include "geometry/core/digital_topology.h"
#include "geometry/scene/section_scene.h"
#include "geometry/reconstruction/section_voronoi_reconstruction.h"
#include "geometry/core/types.h"

namespace xsect {

struct GraphEdge {
  int plane_a = 0, section_a = 0;  ///< the lower (plane, section) of the two
  int plane_b = 0, section_b = 0;
  int cell = -1;                   ///< cell of the arrangement where the lifts meet
  bool operator<(const GraphEdge& o) const;
  bool operator==(const GraphEdge& o) const;
};

struct ConnectivityGraphs {
  std::vector<GraphEdge> g;        ///< method 1, sorted, unique
  std::vector<GraphEdge> g_prime;  ///< method 2, sorted, unique
  /// G'' (Def. 44, symmetric labeling), sorted, unique: not filled by connectivityGraphs; see
  /// branchingDiagram (geometry/delaunay/branching_diagram.h). Proposition 10: G' ⊆ G''.
  std::vector<GraphEdge> g_double_prime;
  /// Observed pieces: the cells (ids, ascending) from which a lift of G_Ω passes an unobserved part
  /// of a face into another cell (its edge is listed in the cell where it meets the other lift).
  /// Empty with whole pieces.
  std::vector<int> cells_left_through_unobserved;
};

/// @param scene        the cutting planes (real and virtual, as given to arrangeSections) and
///                     their section distance rasters.
/// @param arrangement  the section points and their cells.
/// @param method2      the thickening used by method 2.
/// @param withGPrime   compute G' too (costs a method-2 decision per ray step).
ConnectivityGraphs connectivityGraphs(const SectionScene& scene, const SectionArrangement& arrangement,
                                      const SectionVoronoiParams& method2, bool withGPrime);

/// How a graph's components compare with the connected components of a voxel solid: each section
/// is located by its deepest lattice point (the voxel holding it).
struct GraphVoxelCheck {
  int graph_components = 0;          ///< components of the graph on the sections
  int voxel_components = 0;          ///< voxel components that hold at least one section
  int sections_unlocated = 0;        ///< sections whose voxel is outside the solid
  int pairs_joined_by_graph_only = 0;   ///< section pairs together in the graph, apart in voxels
  int pairs_joined_by_voxels_only = 0;  ///< section pairs together in voxels, apart in the graph
  bool same_partition = false;      ///< no pair disagrees (unlocated sections aside)
};
/// @param scene   the planes the arrangement was built on, and their rasters.
/// @param inside  the solid, one byte per voxel of `grid` (the scene's grid or a finer lattice).
GraphVoxelCheck compareWithVoxels(const std::vector<GraphEdge>& edges, const SectionScene& scene,
                                  const SectionArrangement& arrangement, const std::vector<std::uint8_t>& inside,
                                  const GridSpec& grid);
/// The same for a solid stored by blocks (block_grid.h), on its grid.
GraphVoxelCheck compareWithVoxels(const std::vector<GraphEdge>& edges, const SectionScene& scene,
                                  const SectionArrangement& arrangement, const BlockGrid<std::uint8_t>& inside);
/// The same for a solid's components (digital_topology.h), on their grid.
GraphVoxelCheck compareWithVoxels(const std::vector<GraphEdge>& edges, const SectionScene& scene,
                                  const SectionArrangement& arrangement, const SolidComponentIndex& solid);

}  // namespace xsect
