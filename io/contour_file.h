// Ctr2Suf .contour files (the curve networks of Tao Ju's Ctr2Suf, CycleGrouping and Multitopo):
// planes, each with its vertices and the edges between them, every edge labelled with the
// materials on its two sides (0 the background, >= 1 solids). Read into cutting planes with
// sections: the union of the materials, and each material's own.
//
// Layout (whitespace-separated numbers, world units taken as mm):
//   nPlanes
//   per plane:  a b c d        the plane a x + b y + c z + d = 0
//               nV nE          vertex and edge counts
//               x y z          nV lines: the vertices, world coordinates
//               i j left right nE lines: an edge from vertex i to vertex j (0-based, of this
//                              plane), material `left` on its left, `right` on its right
// "Left" of the directed edge i -> j is the side n × (p_j - p_i) points to, n = (a, b, c)
// normalised: the left as seen looking at the plane from the side n points to (in the plane's
// (u, v) frame, u × v = n, a region with its material on the left of its boundary edges is bounded
// by counter-clockwise outer contours and clockwise holes).
#pragma once

#include <string>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// A .contour file's sections.
struct ContourFile {
  /// One cutting plane per file plane, in file order (slice p, named "plane p+1"): the union of
  /// all materials (label 1), the geometry to reconstruct. Observed everywhere; extent the
  /// sections' bounds.
  std::vector<CuttingPlane> planes;
  /// Per plane (index as `planes`), each material's sections (Section::label = the material),
  /// material by material in increasing order; empty when the file has only one material.
  std::vector<std::vector<Section>> labelled;
  /// The materials (>= 1) on some side of some edge, increasing.
  std::vector<int> materials;
};

/// Reads the .contour file at `path`.
/// Planes: normal (a, b, c) normalised, origin the mean of the plane's vertices (the file's d is
/// not trusted; the vertices must lie on one plane), u, v completing a right-handed frame
/// (io/contour_plane.h). A plane without vertices is empty; it lies at distance |d| / |(a, b, c)|
/// from the world origin, on the side nearer the data (so either sign convention of d reads).
/// Sections of material m: the edges with m on exactly one side, turned so that m is on their
/// left, chained into closed contours (at a vertex where several continue, the turn keeping the
/// tightest wedge of m: contours touching at a vertex stay separate rings); counter-clockwise
/// contours are outer rings, clockwise ones holes. The union: the same with the edges between a
/// material and the background 0. Contours are cleaned of repeated vertices; a contour without
/// area is dropped with a warning (into `warnings` when given) naming its plane and material.
/// Throws InputError naming the file, the field (e.g. "plane 3 edge 7": planes from 1, vertices
/// and edges from 0 as the file indexes them) and the line on: a missing, non-numeric or
/// non-finite number; a count that disagrees with the content; a vertex index out of range; an
/// edge from a vertex to itself or listed twice; a negative material, or the same material on both
/// sides; a zero normal; vertices off their plane; edges that do not close into contours (some
/// vertex with more edges of a material coming in than going out); without `repair`, a
/// self-intersecting contour (with `repair`, input.repair_contours, the default: the contours of a
/// material on a plane that cross themselves or each other are made simple rings of the same
/// region, geometry/core/ring_repair.h, with a warning); a
/// clockwise contour inside no counter-clockwise one (the material would be unbounded: left and
/// right swapped); content after the last plane.
ContourFile readContourFile(const std::string& path, std::vector<std::string>* warnings = nullptr,
                            bool repair = true);

}  // namespace xsect
