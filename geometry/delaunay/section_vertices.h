// The section-vertices of method 3 (thesis ch. 3 §1): the sampled section-contours and the points
// added on the branching diagram, each point with the cutting planes it lies on and the cells of
// the arrangement whose boundary it lies on; the contours as rings of point ids, so that contour
// edges can be split (Delaunay conformity) and the sampled sections tested for containment.
// Built from the arrangement's contour points (section_arrangement.h): its contour vertices (one per
// sample spacing along each ring) and trace points (where a contour crosses another plane; such a
// point lies on both planes and bounds the cells on both sides of both), and the corners where
// three planes meet inside a section (vertices of the sub-sections that no contour reaches).
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "geometry/arrangement/section_arrangement.h"
#include "geometry/core/types.h"

namespace xsect {

struct BranchingPoint;

/// A cell a point bounds, with the side of each of the point's planes the cell lies on.
struct PointCell {
  int cell = -1;
  std::array<std::int8_t, 3> side{0, 0, 0};  ///< per plane of the point: -1 or +1 (0: no such plane)
};

struct SectionVertex {
  Vec3 x = Vec3::Zero();                ///< world, mm
  /// The planes it lies on: its own; a trace's plane; for a corner (three planes meeting inside a
  /// section) the other two. -1: none.
  std::array<int, 3> planes{-1, -1, -1};
  int section = -1;                     ///< section of planes[0] whose contour (or inside) it is on
  enum Kind : std::uint8_t { contour, trace, branching, conformity, corner } kind = contour;
  std::vector<PointCell> cells;         ///< 2, 4 or 8 cells (one per side of each plane), by id
  bool on(int plane) const { return planes[0] == plane || planes[1] == plane || planes[2] == plane; }
  /// The index of `plane` in `planes` (0 when absent).
  int slot(int plane) const { return planes[1] == plane ? 1 : planes[2] == plane ? 2 : 0; }
};

/// Key of the undirected edge (a, b) between section-vertices (point ids): the one key every
/// stage of method 3 uses for contour edges, grounded edges and boundary edges.
inline std::uint64_t edgeKey(int a, int b) {
  if (a > b) std::swap(a, b);
  return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
}

/// A sampled ring: point ids in contour order (closed: the last joins the first).
struct SampledRing {
  int plane = -1, section = -1, ring = -1;  ///< ring 0 outer, h + 1 hole h
  std::vector<int> points;
};

struct SectionVertices {
  std::vector<SectionVertex> points;
  std::vector<SampledRing> rings;
  /// Per plane: its sampled sections (rings of plane coordinates, outer then holes), the polygons
  /// the Delaunay structure conforms to.
  std::vector<std::vector<Section>> sampled;
  int cells = 0;
  /// Rings shorter than about three sample spacings that cross another plane: below the
  /// sampling, left out (see sectionVertices).
  int rings_dropped = 0;
};

/// @param planes       the planes of the arrangement (real and virtual).
/// @param arrangement  arrangeSections(planes, spacing).
/// @param branching    points on the branching diagrams, one cell each.
/// Rings the arrangement sampled with fewer than 3 points take evenly spaced vertices of the
/// original ring (in the cells of its first sampled point) when they cross no plane, and are left
/// out when they do. Points within a ten-millionth of the sample spacing are merged.
SectionVertices sectionVertices(const std::vector<CuttingPlane>& planes, const SectionArrangement& arrangement,
                                const std::vector<BranchingPoint>& branching);

/// Plane coordinates of point `id` on `plane` (one of the point's planes).
Vec2 planeCoordinates(const SectionVertices& sv, const std::vector<CuttingPlane>& planes, int id, int plane);

/// The cells (sorted) the contour edge (a, b) of a ring on `plane` lies in: per side of the plane,
/// the cell both endpoints bound, if any.
std::vector<int> edgeCells(const SectionVertices& sv, int a, int b, int plane);

/// Splits edge (ring r, position k → k + 1) at its midpoint: a new point with the edge's cells.
/// Returns the new point's id. Rebuilds nothing else (call resampleSections after splits).
int splitRingEdge(SectionVertices& sv, const std::vector<CuttingPlane>& planes, std::size_t r, std::size_t k);

/// Recomputes sv.sampled from the rings.
void resampleSections(SectionVertices& sv, const std::vector<CuttingPlane>& planes);

}  // namespace xsect
