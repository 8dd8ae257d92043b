// The labeling Φ, the graph G'' and the branching diagrams of the cells' faces (thesis ch. 2 §5.2,
// Def. 44-45), sampled on the section points of the arrangement (section_arrangement.h): the
// branching points B_C that method 3 adds to the contour vertices (ch. 3 §1).
//
// Definition implemented. Let a be a point of section A on plane P, on the side of P facing the
// cell C (normal n of P pointing into C), and x(t) = a + t·n. The ray stays in A's Voronoi cell
// V_C(A) (ch. 2 §2, the Voronoi diagram of the sections S_C on C's boundary) up to lift'(a)
// (Def. 29). For every other plane Q, let D_Q(x) be the distance from x to the part of Q's sections
// lying on ∂C: the points of Q's sections that no cutting plane separates from x (x ∈ C, C convex).
// D_Q is 1-Lipschitz, so D_Q(x(t)) - t does not increase and its first zero t_Q is found by
// bisection. With t_exit the first t where the ray crosses a cutting plane:
//   Φ(a) = the section of the plane Q of smallest t_Q < t_exit that holds the point of Q's sections
//          nearest to x(t_Q) (lift'(a) = x(t_Q) ∈ ∂V_C(Φ(a)): the label of Def. 45, point by point);
//   Φ(a) = none when no t_Q < t_exit (lift'(a) lies on ∂C outside the sections).
// Ties: when other planes' t_Q equal the smallest (to 1e-8 relative), lift'(a) lies on an edge or
// vertex of the Voronoi diagram, in ∂V_C of each of those sections: all of them count for G''
// (Def. 44 asks ∂V_C(B) ∩ lift'(A) ≠ ∅); `label` and the branching points keep the first plane's.
// Sections of P itself never end the ray: their distance to x(t) is at least t.
//  - G''_C (Def. 44): A and B are joined in C when Φ(a) = B for some point a of A and Φ(b) = A for
//    some point b of B, both on the sides facing C (symmetric labeling). Proposition 10: G'_C ⊆
//    G''_C, and G_C ⊆ G'_C (Proposition 5).
//  - Branching points (Def. 45: the projection on C's faces of the 1-skeleton of VorSkel(S_C), the
//    lines across which Φ changes): the midpoint of every pair of lattice samples of one section
//    and cell side that are 4-neighbours on the arrangement's square lattice (spacing
//    sample_spacing_mm, samples at (i + ½, j + ½)·spacing in plane coordinates) and whose labels
//    are two different sections. A midpoint lies within half a spacing of a point where Φ changes.
//    With `withCellExits`, pairs where one label is none count too (where a Voronoi face of two
//    sections meets ∂C outside the sections: not the 1-skeleton of Def. 45).
// Evaluation: D_Q from the raster f_Q (section_distance_field.h) where its four nodes hold exact
// distances and its value is not within a node spacing of the threshold, from the polygons
// elsewhere (the raster is clamped beyond its band; near ties its interpolation would decide
// inside or outside a section wrongly); roots are bracketed to 1e-9 of the ray's length. The
// nearest point of Q's sections at each root is checked for visibility, and where another plane
// hides it t_Q is solved again with the distance to Q's sections clipped to the face of C it can
// see (polygons). Candidate planes Q are those near the section (as for G and G').
// Sampling: Φ is evaluated at the arrangement's contour vertices and lattice samples (not trace
// points). For G'' also at witnesses: where Φ(a) = B and lift'(a) projects into B at b, but no
// sample of B facing C is labelled A, Φ(b) is evaluated too (lift'(b) = lift'(a) in theory, so
// Φ(b) = A unless a third section is as near): a part of B thinner than the lattice (a small
// sub-section, a narrow Voronoi face) is seen there. Branching points come from the lattice only.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geometry/arrangement/connectivity_graph.h"
#include "geometry/arrangement/section_arrangement.h"
#include "geometry/delaunay/delaunay_reconstruction.h"
#include "geometry/scene/section_scene.h"

namespace xsect {

struct BranchingDiagram {
  /// Midpoints of lattice neighbours with different labels, sorted by (cell, plane, section, u, v),
  /// unique; plane coordinates in mm.
  std::vector<BranchingPoint> points;
  /// G'' (Def. 44): sorted, unique, GraphEdge conventions (lower (plane, section) first, `cell`).
  std::vector<GraphEdge> g_double_prime;
  /// Φ per point of the arrangement and side of its plane (0: negative, 1: positive), as the flat
  /// section id (scene.ids()) of the label (the first of tied ones); -1 for none, and for trace
  /// points and sides without a cell (not followed).
  std::vector<std::array<int, 2>> label;
  std::int64_t rays = 0;          ///< (point, side) pairs followed (the side has a cell)
  std::int64_t labelled = 0;      ///< of them, with a label
  std::int64_t hidden_roots = 0;  ///< roots whose nearest section point another plane hid
  std::int64_t polygon_distances = 0;  ///< distance tests done on the polygons, not the raster
  std::int64_t witnesses = 0;     ///< feet of lifts labelled for G'' (see above)
};

/// @param scene          the planes the arrangement was built on (real and virtual) and their
///                       rasters of f_P (same order).
/// @param arrangement    arrangeSections(scene.planes, spacing): its contour vertices and lattice
///                       samples are the points labelled; spacing in mm.
/// @param withCellExits  branching points also where a label changes to none (see above).
/// Parallel over points; deterministic: the same output whatever the thread count. Cost: about
/// 2-3 times connectivityGraphs(..., withGPrime = true) on the same arrangement (measured on
/// random and orthogonal configurations of 10-42 planes).
BranchingDiagram branchingDiagram(const SectionScene& scene, const SectionArrangement& arrangement,
                                  bool withCellExits = false);

}  // namespace xsect
