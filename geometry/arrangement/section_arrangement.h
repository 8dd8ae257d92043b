// Stage 4 (docs/methods.md; thesis ch. 2 §5.1): which cells of the arrangement of the cutting planes the
// sections bound, without building the arrangement (cells holding no section are never met).
// Every section point gets its sign vector against all planes (an exact predicate on its double
// coordinates: CGAL's filtered orientation); the point bounds the cell with that sign vector on
// either side of its own plane. Contour points are added where contour edges cross another plane
// (their sign there is 0: they bound the cells on both sides of it), and the sections are sampled
// on a lattice so that sub-sections without contour vertices (pieces cut out by the traces of
// other planes) are met too. Sub-sections are the (section, cell) pairs found.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// A point of a section: a contour vertex, a contour point added on another plane's trace, or a
/// lattice sample inside the section.
struct SectionPoint {
  int plane = 0;    ///< index into the planes given
  int section = 0;  ///< index into that plane's sections
  Vec2 p = Vec2::Zero();  ///< plane coordinates, mm
  enum Kind : std::uint8_t { vertex, trace, sample } kind = sample;
  /// Cells on the negative and positive side of the point's own plane (ids into the cells found).
  /// A trace point also bounds the cells on both sides of the plane it lies on (the thesis'
  /// duplication of such vertices): `cell` are those on that plane's positive side, `cell_alt`
  /// those on its negative side.
  std::array<int, 2> cell{-1, -1};
  int trace_plane = -1;  ///< trace points: the plane whose trace they lie on
  /// Trace points: the cells on the negative side of the trace plane, on either side of the own.
  std::array<int, 2> cell_alt{-1, -1};
  /// Contour points (vertex, trace): the ring of the section they lie on (0: outer, h + 1: hole h)
  /// and their place along it (v + t on the edge from ring vertex v to v + 1): sorting a ring's
  /// points by `along` gives its sampled contour in order. -1 and 0 for lattice samples.
  int ring = -1;
  double along = 0;
};

struct SubSection {
  int plane = 0, section = 0;
  int side = 1;   ///< +1: the cell lies on the side the plane's normal points to
  int cell = -1;  ///< id of that cell
  int points = 0; ///< section points found in it
};

/// The sign-vector keys of the cells found (opaque; see cellsAround).
struct ArrangementKeys;

struct SectionArrangement {
  int cells = 0;                     ///< cells of the arrangement bounded by at least one section
  std::vector<SubSection> sub_sections;
  std::vector<SectionPoint> points;  ///< in plane, section, then point order
  int trace_points = 0;              ///< contour points added on traces of other planes
  /// Trace points that also lie, up to rounding, on a third plane through the same line (a fan's
  /// axis crossing the sections): three or more planes of one pencil meet there, which the thesis'
  /// general position excludes (ch. 3 §2.4). Each is a crossing where the sign vectors against those
  /// planes are decided by rounding alone. `pencil_planes` is one such triple (-1: none).
  int pencil_crossings = 0;
  std::array<int, 3> pencil_planes{-1, -1, -1};
  double sample_spacing_mm = 0;
  std::shared_ptr<const ArrangementKeys> keys;  ///< for cellsAround
};

/// @param planes   all cutting planes (real and virtual: virtual planes bound cells too).
/// @param spacing  lattice spacing for the samples inside sections, mm (> 0).
/// Deterministic: cell ids follow the order in which points are listed.
SectionArrangement arrangeSections(const std::vector<CuttingPlane>& planes, double spacing);

/// A cell's sign-vector key (as CellsAround::keys): cells met or not by section points.
using CellKey = std::array<std::uint64_t, 2>;
/// The key of cell `cell` (an id of the arrangement).
CellKey cellKey(const SectionArrangement& arrangement, int cell);
/// The key of the cell across plane `plane` from the cell with key `key` (the same sides of every
/// other plane).
CellKey keyAcross(const SectionArrangement& arrangement, const CellKey& key, int plane);
/// The id of the cell with key `key`, or -1 when no section point bounds it.
int cellOfKey(const SectionArrangement& arrangement, const CellKey& key);

/// The cells around point x lying on the planes `on` (1 to 3 of them): one per choice of side of
/// each, the side of on[k] being bit k of the index (set: positive). x's signs against every other
/// plane are exact (as for the arrangement's points).
struct CellsAround {
  std::vector<int> cells;  ///< -1 for a cell that no section point of the arrangement bounds
  /// The cells' sign-vector keys (equal keys: the same cell), to number the cells that are -1.
  std::vector<std::array<std::uint64_t, 2>> keys;
};
CellsAround cellsAround(const SectionArrangement& arrangement, const std::vector<CuttingPlane>& planes,
                        const Vec3& x, const std::vector<int>& on);

/// The key of the cell holding x (exact signs against every plane of `planes`, the planes the
/// arrangement was built on; a point on a plane counts on its positive side, as the
/// arrangement's points do); cellOfKey gives its id.
CellKey cellKeyAt(const SectionArrangement& arrangement, const std::vector<CuttingPlane>& planes, const Vec3& x);

}  // namespace xsect
