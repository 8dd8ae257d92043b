// Method 2 (thesis ch. 2 §2, Def. 27-28) evaluated on a voxel grid.
// In a cell C of the arrangement, the Voronoi diagram of the sections S_C decides: a point x of the
// Voronoi cell V_C(A) of section A is in R' when its orthogonal projection on A's plane lies in A.
// A section point s lies on ∂C, seen from x, exactly when the open segment (x, s) crosses no
// cutting plane ("s is visible from x"); so, with d(x, S_C) the distance to the nearest visible
// section point,
//     x ∈ R'  ⇔  some plane P has a visible projection p of x inside a section of P, with
//                |x - p| = d(x, S_C)                                 (ties count, Def. 28).
// Only the facets of x's cell can hide a section point of ∂C or hold one: the cell is built once
// per group of voxels sharing it (cell_facets.h, a box clipped by the planes nearest first), and
// the evaluation walks its facets by increasing distance, stops as soon as the nearest visible
// in-section projection (height H_in) is found, then checks that no visible section point of a
// nearer facet lies closer than H_in (exactly, by clipping the plane's contours to the visible
// face, when another plane's trace passes near the projection). A projection on the nearest plane
// that lies in a section is visible and nearest of all: such a voxel is decided there (R ⊆ R').
// A plane that meets the cell only along an edge or at a vertex (planes sharing an axis, a fan) is
// not a facet: a section point there lies on the adjacent facets too, where sections that agree
// along their common lines (the thesis' conformity) hold it as well.
//
// Thickened planes (Fig. 2.6): within `slab_mm` of its nearest plane a point belongs to R' exactly
// when it belongs to R (its projection on that plane lies in a section). Lifts that reach a face of
// C outside its sections therefore stop just short of it, R' meets the planes only in the sections
// (conformity), and pieces of neighbouring cells are glued along sections only. R ⊆ R' holds point
// by point (Theorem 18): a point of R has an in-section projection on its nearest plane.
//
// Exactness: visibility is decided with the planes' equations, distances to contours from the
// polygons; whether a projection lies in a section is read from the f_i rasters (as in method 1),
// so a decision may differ from the definition only where a projection lies within the rasters'
// interpolation error of a contour. tests/test_method2.cpp compares with a brute-force
// evaluation of Def. 27-28 away from such ties (1e-3 mm).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/core/block_grid.h"
#include "geometry/scene/section_distance_field.h"
#include "geometry/core/types.h"

namespace xsect {

struct SectionVoronoiParams {
  /// Half-thickness of the thickened cutting planes, mm (>= 0). On a grid of spacing h, a value of
  /// at least h·√3/2 makes every 26-connected path of voxels that crosses a plane meet it.
  double slab_mm = 0.0;
};

struct SectionVoronoiField {
  ScalarField value;                  ///< in-plane signed distance, ±band; negative = in R'
  std::vector<float> plane_distance;  ///< distance to the nearest cutting plane, mm
  std::vector<int> nearest_plane;     ///< index of that plane
  /// For voxels in R': the plane of the section A with x ∈ V_C(A) and proj(x) ∈ A; -1 elsewhere.
  std::vector<int> section_plane;
  /// For voxels in R': d(x, np'(x)), the height of x above A's plane (its place on the lift
  /// segment [a, lift'(a)]); 0 elsewhere. Its maximum bounds the lift lengths used by Thm 20.
  std::vector<float> lift_height;
  std::int64_t exact_face_tests = 0;  ///< clipped-face distance evaluations (statistics)
  std::int64_t cells_clipped = 0;     ///< arrangement cells built for voxels off the thickened planes (statistics)
};

/// @param planes    cutting planes (real and virtual); planes[i] uses fields[i] and its sections.
/// @param fields    section distance rasters, one per plane (sectionDistanceField).
/// @param grid      voxel centres to evaluate (mm).
/// @param params    thickening of the planes.
/// @param progress  optional, called with the blocks done and the blocks in all (from the calling thread).
/// Deterministic whatever the thread count: a voxel's verdict follows from its position; the value
/// stored outside R' may depend on the voxel its cell was clipped around, the first of the 8³
/// block in that cell. Dense arrays (small grids,
/// tests); the run uses forEachSectionVoronoiBlock.
SectionVoronoiField sectionVoronoiReconstruction(const std::vector<CuttingPlane>& planes,
                                                 const std::vector<SectionDistanceField>& fields,
                                                 const GridSpec& grid,
                                                 const SectionVoronoiParams& params,
                                                 const std::function<void(std::int64_t, std::int64_t)>& progress = {});

/// Method 2 on one block of 8³ voxels (block_grid.h), by BlockGrid's offset(); voxels of the
/// block beyond the grid repeat the block's first voxel. Fields as SectionVoronoiField's.
struct SectionVoronoiBlock {
  static constexpr int kVoxels = BlockGrid<float>::kVoxels;
  std::array<float, kVoxels> value, plane_distance, lift_height;
  std::array<int, kVoxels> nearest_plane, section_plane;
};

/// Sets the voxels of `block` (its first voxel at `origin`) that lie beyond the grid to its first
/// voxel's values, so that a block uniform within the grid is uniform.
inline void repeatFirstBeyondGrid(const GridSpec& grid, const std::array<int, 3>& origin, SectionVoronoiBlock& block) {
  forEachBeyondGrid(grid, origin, [&](int o) {
    const std::size_t q = std::size_t(o);
    block.value[q] = block.value[0];
    block.plane_distance[q] = block.plane_distance[0];
    block.nearest_plane[q] = block.nearest_plane[0];
    block.section_plane[q] = block.section_plane[0];
    block.lift_height[q] = block.lift_height[0];
  });
}

struct SectionVoronoiStatistics {
  std::int64_t exact_face_tests = 0;
  std::int64_t cells_clipped = 0;
};

/// Method 2 block by block: visit(b, values) for every block b of BlockGrid's numbering on `grid`,
/// from several threads at once (each block once): no per-voxel array of the whole grid (issue
/// 17). Parameters as sectionVoronoiReconstruction's; `statistics` (optional) receives its counts.
void forEachSectionVoronoiBlock(const std::vector<CuttingPlane>& planes,
                                const std::vector<SectionDistanceField>& fields, const GridSpec& grid,
                                const SectionVoronoiParams& params,
                                const std::function<void(std::int64_t, const SectionVoronoiBlock&)>& visit,
                                const std::function<void(std::int64_t, std::int64_t)>& progress = {},
                                SectionVoronoiStatistics* statistics = nullptr);

/// Method 2 at single points (for the connectivity graph along lifts): the same decision as the
/// grid evaluation, among the facets of the point's cell.
class SectionVoronoiPoints {
 public:
  struct Answer {
    bool inside = false;     ///< x ∈ R'
    int section_plane = -1;  ///< plane of the section whose lift holds x (inside only)
    float lift_height = 0;   ///< x's height on that lift, mm (inside only; the grid's lift_height)
  };
  /// The cell of the arrangement the last query clipped (its facets), kept by the caller between
  /// queries that follow one path: a query in the same cell reuses it. Filled by at().
  struct CellMemo {
    std::vector<int> facets;        ///< facet planes, ascending
    std::vector<signed char> sides; ///< the cell's side of each facet (+1: the normal's side)
    Vec3 origin = Vec3::Zero(), lo = Vec3::Zero(), hi = Vec3::Zero();
    double radius = -1;             ///< no point of the cell lies farther from origin (mm); < 0: none
    std::int64_t reuses = 0;        ///< queries that found their point in this memo's cell
  };
  SectionVoronoiPoints(const std::vector<CuttingPlane>& planes,
                       const std::vector<SectionDistanceField>& fields,
                       const SectionVoronoiParams& params);
  ~SectionVoronoiPoints();
  SectionVoronoiPoints(const SectionVoronoiPoints&) = delete;
  SectionVoronoiPoints& operator=(const SectionVoronoiPoints&) = delete;
  /// Thread-safe; `memo` (optional, one per calling thread) carries the last cell along a path.
  Answer at(const Vec3& x, CellMemo* memo = nullptr) const;

 private:
  struct Impl;
  Impl* impl_;
};

}  // namespace xsect
