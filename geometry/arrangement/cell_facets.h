// The facet planes of the cell of the arrangement that holds a point (thesis ch. 1 §2: the cells
// of the arrangement of the cutting planes; ch. 2 §2: a cell's sections S_C lie on its facets).
// The cell is built as a box clipped by the half-space of each plane on the point's side, nearer
// planes first; a plane farther from the point than every vertex of the clipped box cannot cut it,
// so the clipping stops there and the cost follows the cell's facets, not the number of planes.
//
// Why not CGAL's halfspace_intersection_3 (cell_polytope.h, exact): method 2 needs the facets of
// tens of thousands of cells per run (one per group of voxels), about 5 µs each here against
// about 100× that with the exact kernel; only the set of facet planes is used, and a plane that
// cuts the cell by less than the tolerance (far below a voxel) changes no decision of method 2.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// A convex polytope as its faces (each a convex polygon with the plane it lies on), cut down one
/// half-space at a time. Reused between cells (no allocation once warm).
class ClippedBox {
 public:
  /// Starts from the box [lo, hi] (mm); its faces carry plane id -1.
  void reset(const Vec3& lo, const Vec3& hi, double tolerance_mm);
  /// Keeps {y : side·(n·y − d) ≥ 0} (|n| = 1, side ±1); the new face carries `id`. Returns
  /// whether anything was cut off (a vertex beyond the tolerance on the other side).
  bool clip(const Vec3& n, double d, int side, int id);
  /// Largest distance from x to a vertex, mm (0 when empty).
  double farthestVertexDistance(const Vec3& x) const;
  bool empty() const { return plane_.empty(); }
  /// Ids of the faces' planes, ascending, box faces (-1) left out.
  void facetPlanes(std::vector<int>* out) const;

 private:
  double tolerance_ = 0;
  std::vector<Vec3> points_, nextPoints_, cap_;  // faces' vertices, one face after another
  std::vector<int> start_, plane_, nextStart_, nextPlane_;
  std::vector<double> value_;
  std::vector<std::pair<double, int>> byAngle_;
  std::int64_t clips_ = 0;

 public:
  /// Half-spaces offered to clip() since construction (for tests of the early stop).
  std::int64_t clipsOffered() const { return clips_; }
};

/// The facet planes of the cell holding x0 (x0's side of every plane; a plane through x0 counts x0
/// on its normal's side).
/// @param normals, offsets  the planes n·y = d, unit normals.
/// @param order             the planes to consider, with lower_bound[k] a lower bound of order[k]'s
///                          distance to x0 (mm), increasing: the clipping stops at the first plane
///                          whose bound exceeds the farthest vertex.
/// @param lo, hi            a box holding x0 and everything the cell is asked about, mm.
/// @param tolerance_mm      cuts shallower than this are ignored.
/// @param box               scratch (reused).
/// @param facets            receives the facet planes, ascending.
/// @return the largest distance from x0 to a point of the cell within the box, mm.
double cellFacets(const Vec3& x0, const std::vector<Vec3>& normals, const std::vector<double>& offsets,
                const std::vector<int>& order, const std::vector<double>& lower_bound, const Vec3& lo,
                const Vec3& hi, double tolerance_mm, ClippedBox& box, std::vector<int>* facets);

}  // namespace xsect
