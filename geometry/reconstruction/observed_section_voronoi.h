// Method 2 (thesis ch. 2 §2, Def. 27-28) on observed pieces (issue 20; docs/methods.md, "Observed pieces").
// A slice's plane P was seen only on its piece Ω_P (observed_piece.h). Method 2 decides a point x
// of a cell C by the sections visible from x on ∂C: with pieces, ∂C is made of pieces, and where a
// plane was not observed the cell, and so x's lift, is not known from the data. The definition
// xsect computes, h(x) = d(x, np'(x)) being the height of x on its lift (method 2 on whole planes,
// section_voronoi_reconstruction.h) and R_Ω method 1 on the pieces (nearest_plane_reconstruction.h):
//
//     R'_Ω = R_Ω ∪ { x ∈ R' : p ∈ Ω_A, and within B(x, h(x)) every cutting plane is observed
//                             (Q ∩ B(x, h(x)) ⊆ Ω_Q for every Q) or no section point but p lies },
// p being x's projection on the plane A of the section whose lift holds x.
//
// Why: Def. 27-28 with each plane replaced by its piece (visibility through pieces, the nearest
// point of Ω_P for the projection) keeps such an x in R'. On a ball where every plane is observed
// the pieces and the planes coincide, so the section points visible from x within h(x) are the
// same (a segment from x shorter than h(x) crosses Q inside B(x, h(x)), where Q is observed). On a
// ball that holds no section point but p, whatever the pieces reveal lies farther than p. In both
// cases p, visible and in a section, is the nearest visible section point, and (as p ∈ Ω_A) the
// nearest point of Ω_A to x. Otherwise a lift would pass where some plane was not observed, towards sections the
// pieces may reveal; it is not followed, and x is decided by method 1 on the pieces instead
// (beyond the images the nearest piece's sections extend). With every piece whole, R_Ω = R ⊆ R'
// (Theorem 18) and every ball qualifies: R'_Ω = R', and this function is
// forEachSectionVoronoiBlock itself.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/core/section_locator.h"
#include "geometry/reconstruction/section_voronoi_reconstruction.h"
#include "geometry/scene/observed_piece.h"

namespace xsect {

struct ObservedSectionVoronoiStatistics {
  SectionVoronoiStatistics voronoi;    ///< method 2's own counts (on whole planes)
  std::int64_t lift_voxels_kept = 0;   ///< voxels of R' \ R_Ω whose ball qualifies: kept in R'_Ω
  std::int64_t lift_voxels_dropped = 0;  ///< voxels of R' \ R_Ω whose lift passes an unobserved part
  std::int64_t pieces_voxels_added = 0;  ///< voxels of R_Ω \ R' (the pieces' method 1 holds them)
};

/// The definition's test for a point x of R' \ R_Ω: x lies on the lift of a section of plane
/// `lifted` at height h (method 2's lift_height); it is kept in R'_Ω when its foot (x's projection
/// on that plane) lies in the plane's piece and, within B(x, h), every plane is observed or no
/// section point but the foot lies (exact distances to the section polygons). Used by the grid
/// evaluation below and by G' along lifts (connectivity_graph.h).
class ObservedLiftTest {
 public:
  /// @param locators  one per plane, over its sections (empty for a plane without sections).
  ObservedLiftTest(const std::vector<CuttingPlane>& planes, const std::vector<ObservedPiece>& pieces,
                   const std::vector<SectionLocator>& locators)
      : planes_(planes), pieces_(pieces), locators_(locators) {}
  /// @param candidates  planes that may meet B(x, h) (a superset: planes farther than h are skipped).
  bool keeps(const Vec3& x, double h, int lifted, const std::vector<int>& candidates) const;

 private:
  const std::vector<CuttingPlane>& planes_;
  const std::vector<ObservedPiece>& pieces_;
  const std::vector<SectionLocator>& locators_;
};

/// R'_Ω block by block, as forEachSectionVoronoiBlock gives R' (parameters as there; `pieces` one
/// per plane, observedPieces()). Whether another plane's section reaches the ball is decided on
/// the polygons. Values of a voxel of R' kept by its ball are method 2's
/// (value, deciding section's plane, lift height); every other voxel has method 1's values on the
/// pieces (section plane: the nearest piece's plane for voxels of R_Ω, -1 outside). The distance
/// and nearest plane are the pieces' (method 1's) for every voxel, so the repair's evidence next to
/// a plane is taken only where the plane was observed; method 2's nearest plane -1 (no plane's
/// sections reach x by projection: outside evidence) is kept where x stays outside. Memory: method
/// 1's values on the pieces are kept for the grid (about 12 B per voxel in blocks the boundary or
/// the planes' bisectors pass through) until method 2 has run. Deterministic whatever the thread
/// count.
void forEachObservedSectionVoronoiBlock(const std::vector<CuttingPlane>& planes,
                                        const std::vector<SectionDistanceField>& fields,
                                        const std::vector<ObservedPiece>& pieces, const GridSpec& grid,
                                        const SectionVoronoiParams& params,
                                        const std::function<void(std::int64_t, const SectionVoronoiBlock&)>& visit,
                                        const std::function<void(std::int64_t, std::int64_t)>& progress = {},
                                        ObservedSectionVoronoiStatistics* statistics = nullptr);

}  // namespace xsect
