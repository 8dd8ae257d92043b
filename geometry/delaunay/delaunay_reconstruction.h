// Method 3 (thesis ch. 3): the Delaunay reconstruction R'', Boissonnat-Geiger generalised to
// unorganised planes. In every cell C of the arrangement that sections bound (section_arrangement.h):
//  - the section-vertices: the sampled contours of the sub-sections on C's faces (the arrangement's
//    contour vertices and trace points, in ring order), the branching points given for C
//    (branching_diagram.h; Def. 45), and contour midpoints added until every contour edge is an
//    edge of the Delaunay triangulation (the Delaunay conformity condition of ch. 3 §1);
//  - D0 = their 3D Delaunay triangulation (CGAL), tetrahedra typed by how their vertices lie on the
//    cutting planes (T_vf, T_ee, T_evv, T_vvvv; Fig. 3.3), grounded edges and triangles classified
//    as contour, internal or external against the sampled sections;
//  - D1 = D0 without external tetrahedra (Def. 47) and, given G'', without the tetrahedra joining
//    sections of two of its components (cell_complex.h, markUnjoined); D2 = the maximal subset of
//    D1 solid at every grounded edge and section-vertex (shell pruning, Def. 48-50; Proposition
//    11: the order of elimination does not matter); D3 = D2 plus tetrahedra of D1 that meet it in 2, 3 or 4 faces
//    and stay solid (cell_complex.h says where this departs from the thesis' T_vf/T_ee-only
//    step 2 and T_evv/T_vvvv-only step 3, and why).
// Gluing the cells (§2, "Solidity and Topological Correctness"): two cells triangulate a shared
// section differently (their branching points differ; rounding makes points of a tilted plane
// not exactly coplanar), so the boundary on each cutting plane is not read from the tetrahedra:
// the plane's section-vertices of both sides are triangulated once in the plane (CGAL constrained
// Delaunay, the contour edges and the edges where either side's solid leaves the plane as
// constraints), and a triangle of that triangulation is a boundary face when exactly one side's
// solid covers it. The boundary is the cells' non-grounded boundary faces plus those flat faces:
// conformal to the contours by construction, no voxel meshing.
// Where the glued boundary is still singular, the pinch is resolved so that the mesh is a closed
// 2-manifold whose Betti numbers are the ones reported: at an edge in 4, 6, ... triangles (solid
// wedges touching along it: under a branching line in a section that ends the object, Fig. 3.14,
// or pieces of two cells meeting on a trace) the wedges are joined along the edge, as the section
// they touch joins them (the thickened planes of §2, Fig. 3.8b); an edge that joining leaves
// singular at both its ends (no point inside the section to part the sheets at) is first split at
// its midpoint, and only one still singular then is kept apart; at a vertex whose link is
// several discs (pieces touching at one point, Fig. 3.8a) each disc gets its own copy of the
// vertex, so the pieces are apart. The split halves of an edge keep its pairing (paired again by
// angle, two nearly coplanar faces rounded into different orders at the two halves, and the
// midpoint then parted nothing: 800 random planes through the genus-2 solid left two edges in four
// faces). A hole bounded by three or four edges in one face each whose vertices lie on one
// cutting plane is a flat face the plane's triangulation lost to rounding (a crossing of its
// constraints within a hundredth of a sample spacing of a trace point, or a trace point 0.005 mm
// from a corner of three planes, splits slivers off whose centroids are misjudged: 400 random
// planes through the genus-2 solid left a triangle, 300 planes two quadrilaterals) and is closed
// by that polygon (holes_closed). A component of the boundary whose mean thickness (3 volume /
// area) is below a thousandth of the sample spacing bounds no volume (a sliver tetrahedron the
// pinches parted from the solid or such a void, a flat sheet lying twice on a plane, slivers along
// nearly collinear points of a plane) and is dropped (flat_shells_dropped; an open one only below
// a square of the sample spacing). The repairs are in boundary_repairs.h. What still is not a
// closed 2-manifold is counted (open_edges); the pipeline then meshes R'''s voxelisation instead
// (pipeline/mesh_stage.h).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/arrangement/connectivity_graph.h"
#include "geometry/arrangement/section_arrangement.h"
#include "geometry/core/types.h"
#include "geometry/delaunay/boundary_repairs.h"
#include "geometry/delaunay/cell_tunnels.h"
#include "geometry/delaunay/tetrahedron_set.h"

namespace xsect {

/// A point added on the branching diagram of a face of a cell (Def. 45): inside section
/// `section` of plane `plane`, used by the cell `cell` only.
struct BranchingPoint {
  int cell = -1;
  int plane = -1;
  int section = -1;
  Vec2 p = Vec2::Zero();  ///< plane coordinates, mm
};

/// Tetrahedra of D0 by type (Fig. 3.3), over all cells. `flat`: all four vertices on one plane
/// (zero volume up to rounding; never part of the solid).
struct TetrahedronTypes {
  std::int64_t vf = 0, ee = 0, evv = 0, vvvv = 0, flat = 0;
};

struct DelaunayStats {
  int cells = 0;                          ///< cells with at least one tetrahedron in D0
  std::int64_t section_vertices = 0;      ///< points triangulated, summed over cells
  std::int64_t branching_points = 0;      ///< of them, branching points
  std::int64_t conformity_points = 0;     ///< contour midpoints added for Delaunay conformity
  /// Contour edges still not Delaunay edges after the 8 rounds of splitting (their tetrahedra are
  /// typed from the midpoint test; 0 on every input measured).
  std::int64_t contour_edges_not_delaunay = 0;
  TetrahedronTypes d0;                    ///< D0's tetrahedra by type
  std::int64_t external = 0;              ///< removed by step 1 (Def. 47)
  std::int64_t unjoined = 0;              ///< not external, removed by step 1 as joining two components of G''
  std::int64_t d1 = 0, d2 = 0, d3 = 0;    ///< tetrahedra kept after steps 1 (and the cell cuts), 2, 3
  std::int64_t flat_faces = 0;            ///< boundary triangles lying in a cutting plane
  std::int64_t constraint_crossings = 0;  ///< rim edges of the two sides that crossed (new vertices)
  int singular_edges = 0;     ///< edges of the glued boundary in 4, 6, ... triangles (joined)
  int singular_vertices = 0;  ///< vertices of the glued boundary with several umbrellas (split)
  int open_edges = 0;         ///< edges in an odd number of triangles (a defect: the mesh is not closed)
  int welded_vertices = 0;    ///< boundary vertices within 1% of the sample spacing of another, welded
  int holes_closed = 0;       ///< three- and four-edge holes on one cutting plane closed as flat faces
  int flat_shells_dropped = 0;  ///< boundary components thinner than a thousandth of the sample spacing
  int cells_unseen = 0;       ///< cells no arrangement point met (ids arrangement.cells and up)
  int rings_dropped = 0;      ///< rings below the sampling that cross a plane, left out (SectionVertices)
  int cell_pairs_cut = 0;     ///< section pairs left unjoined in a cell to cut its tunnels (cell_cycles.h)
  int cell_tunnels_cut = 0;   ///< the tunnels (b1) those cuts took from their cells
  std::int64_t cell_tetrahedra_cut = 0;  ///< tetrahedra of D1 those cuts left out
};

struct DelaunayReconstruction {
  /// ∂R'': every triangle oriented outwards; its vertices are section-vertices (contour points
  /// lie exactly on the sampled contours).
  TriangleMesh mesh;
  /// D3's tetrahedra over all cells (world coordinates, mm), in cell order: R'' is their union.
  TetrahedronSet tetrahedra;
  /// Section pairs that a tetrahedron of D3 joins, per cell (a vertex on each): the connectivity
  /// that R'' realises, sorted and unique.
  std::vector<GraphEdge> connections;
  DelaunayStats stats;
  /// The weld (a hundredth of the sample spacing) and the thickness below which a shell bounds
  /// no volume (a thousandth), as the boundary's repairs used them.
  BoundaryTolerances tolerances;
};

/// @param planes       every cutting plane the arrangement was built on (real and virtual).
/// @param arrangement  arrangeSections(planes, spacing): its contour vertices (one per spacing
///                     along each ring) and trace points, in ring order, are the contour samples.
/// @param branching    branching points per cell (may be empty: Boissonnat 1988 without them).
/// @param progress     optional, called with (cells done, cells) from the calling thread.
/// @param joinable     G'' (Def. 44; branching_diagram.h), whose components R'' may not join;
///                     nullptr: no such restriction (Boissonnat 1988, without branching points).
/// @param tunnels      whether tunnels of a cell that its sections do not carry are cut
///                     (cell_cycles.h) or kept (the thesis' D3).
/// Deterministic: the same input gives the same mesh whatever the thread count.
DelaunayReconstruction delaunayReconstruction(const std::vector<CuttingPlane>& planes,
                                              const SectionArrangement& arrangement,
                                              const std::vector<BranchingPoint>& branching,
                                              const std::function<void(std::int64_t, std::int64_t)>& progress = {},
                                              const std::vector<GraphEdge>* joinable = nullptr,
                                              CellTunnels tunnels = CellTunnels::cut);

}  // namespace xsect
