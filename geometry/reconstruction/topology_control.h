// Topology control (issue 51): the solid the sections allow with the Betti numbers the user knows,
// or the simplest one, chosen cell by cell among joins of the sections.
//
// Every method's solid R is the union of its cells' solids R_C (thesis ch. 1 §1.2: the
// arrangement of the planes), and in each cell R_C joins some of the sections on the cell's faces
// (the graphs G, G', G'': ch. 1 §3, ch. 2 §2). The alternatives of a cell are which joins it makes:
//  - a join the method made is a *contact patch* of the sampled solid: a 26-connected set of
//    voxels of the cell whose lifts come from two different sections (each voxel labelled with
//    the section its lift comes from, thesis remark after Def. 17) and touch each other. It is
//    *cut* by removing the patch's voxels; removing half of it (the side of a plane through its
//    centre across its longest axis) keeps the join and breaks a ring-shaped contact, a tunnel
//    the join graph does not see;
//  - a join between two sections on different faces of the cell is *added* as a tube inside the
//    cell from the deepest sample point of one to the deepest of the other (radius: half the
//    smaller depth, at least 1.5 voxels; the cell is convex, so the segment lies in it, and the
//    tube is clipped to it); between two sections the cell joins already, the tube may fill the
//    tunnel between two of their contacts (where they cross at a trace, contacts no cut can remove).
//  - a cell is *mended* (cell_mends.h): a gap that a ball closing of radius 1-3 voxels fills in
//    the cell is filled (the sections it touches are then joined in the cell), a neck that an
//    opening removes is cut (a join whose contact it removes whole is cut with it). A mend only
//    removes tunnels and cavities: one that changes b0 or makes a tunnel or a cavity is not kept
//    (components are the joins' business, and a tunnel a mend makes is about a voxel wide).
// A voxel within one voxel of a real plane changes only to what the plane's sections say at its
// projection (cell_mends.h, planesAllow), so the cut of the solid by every plane (its sections)
// is unchanged; a patch none of whose voxels may be removed is forced.
//
// The search is greedy, cheapest change first (cost: voxels removed or added, so that thin
// contacts, the spurious tunnels between sparse planes, go before wide ones; ties in a fixed
// order). The join graph (nodes: the sections; edges: the joins kept) says what a change can do:
// cutting a bridge splits a component, cutting another join removes a tunnel, adding a join
// between components merges them, adding one within a component makes or fills a tunnel; only
// changes that can move the solid toward the goal are tried, and not those whose neighbourhood
// shows they cannot (with no cavity now nor wanted: a removal enclosing voxels makes a cavity;
// otherwise b1 comes down only when the Euler characteristic goes up, eulerCharacteristicChange,
// which leaves 2-10% of the candidates to evaluate on real contour sets). Each is applied to a copy, made
// well-composed (digital_topology.h), and kept when its Betti numbers (voxelBetti) do:
//  - target [b0, b1, b2]: each b_i moves toward target_i without passing it, and the sum of
//    |b_i - target_i| decreases. When no change of a pass does, the first that decreases the sum
//    by passing a target is kept, else the first that leads to Betti numbers as near and not met
//    before (a cut that removed two tunnels where one was asked for, after which a tube makes one);
//  - simplest: no Betti number grows and their sum decreases; with min_feature_mm > 0, joins
//    wider than it (width: sqrt(patch voxels / 2) voxels, in mm) are not cut.
// It stops at the target, when no change is left to try, or after max_evaluations changes
// evaluated (Betti computations of the box).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/arrangement/connectivity_graph.h"
#include "geometry/arrangement/section_arrangement.h"
#include "geometry/core/digital_topology.h"
#include "geometry/core/named_choice.h"
#include "geometry/core/types.h"
#include "geometry/reconstruction/topology_features.h"
#include "geometry/reconstruction/topology_goal.h"
#include "geometry/scene/section_distance_field.h"

namespace xsect {

/// What a change does in its cell.
enum class CellChangeKind {
  join_cut,     ///< a contact patch removed: the join is gone from the cell
  join_halved,  ///< half a patch removed: the join stays, a ring-shaped contact is broken
  join_added,   ///< a tube added between two sections
  gap_filled,   ///< a gap a ball closing fills (cell_mends.h): joins the sections it touches
  neck_cut      ///< a neck a ball opening removes (cell_mends.h): a join whose contact it removes is cut
};

/// The names report.json gives the kinds.
inline constexpr std::array<NamedChoice<CellChangeKind>, 5> kCellChangeKinds{
    {{CellChangeKind::join_cut, "join_cut"},
     {CellChangeKind::join_halved, "join_halved"},
     {CellChangeKind::join_added, "join_added"},
     {CellChangeKind::gap_filled, "gap_filled"},
     {CellChangeKind::neck_cut, "neck_cut"}}};

/// One change of one cell.
struct CellChange {
  CellChangeKind kind = CellChangeKind::join_cut;
  /// Flat section ids (section_ids.h), sorted: a join's two; a mend's, those it touches.
  std::vector<int> sections;
  int cell = -1;                     ///< the arrangement's cell id, -1 where no section point bounds it
  Vec3 at = Vec3::Zero();            ///< the change's centre, mm
  std::int64_t voxels = 0;           ///< voxels removed or added
  /// cut: the patch's width; added: the tube's diameter; a mend: its ball's diameter.
  double width_mm = 0;
  Betti after{0, 0, 0};              ///< the solid's Betti numbers after it
};

struct TopologyControl {
  Betti before{0, 0, 0}, after{0, 0, 0};
  int joins = 0;          ///< contact patches found inside cells
  int joins_forced = 0;   ///< of them, none of whose voxels the planes let go (planesAllow)
  int joins_possible = 0; ///< pairs of sections on different faces of a cell (tubes that may be added)
  int mends_possible = 0; ///< gaps to fill and necks to cut found (cell_mends.h)
  int evaluated = 0;      ///< changes tried
  bool reached = true;    ///< mode target: `after` is the target
  std::vector<CellChange> changes;
  /// The (section, section, cell) joins no patch of which is left, and those added, as graph edges
  /// (sorted): the method's graph less the first and with the second is the chosen solid's.
  std::vector<GraphEdge> edges_cut, edges_added;
  /// The chosen solid's handles and cavities with their sizes and places (topology_features.h),
  /// when its box holds at most kMaxFeatureVoxels voxels (features_voxels: the box's voxels).
  std::vector<TopologyFeature> features;
  bool features_computed = false;
  std::int64_t features_voxels = 0;
  double seconds = 0;
};

/// @param inside       the solid on `grid`, 1 = in; changed in place (cut joins removed, the
///                     result well-composed).
/// @param source       per voxel of `grid`, 1 + the flat id of the section the voxel's lift comes
///                     from (0: none).
/// @param planes       every plane of the arrangement (real first, then the end planes).
/// @param real_planes  how many of `planes` are real (hold sections).
/// @param fields       per plane, its sections' distance raster (the deepest points of the joins added).
/// @param arrangement  arrangeSections(planes, ...): the cells, their ids and the sections' sample points.
/// @param progress     optional, called with the changes tried and goal.max_evaluations after each
///                     change kept, and with the changes tried twice at the end.
/// Deterministic. Throws std::invalid_argument on mismatched sizes.
TopologyControl controlTopology(std::vector<std::uint8_t>& inside, const GridSpec& grid,
                                const std::vector<std::uint16_t>& source, const std::vector<CuttingPlane>& planes,
                                std::size_t real_planes, const std::vector<SectionDistanceField>& fields,
                                const SectionArrangement& arrangement, const TopologyGoal& goal,
                                const std::function<void(std::int64_t, std::int64_t)>& progress = {});

}  // namespace xsect
