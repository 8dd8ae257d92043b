// The thesis' sampling conditions checked per cell of the arrangement, and a verdict (issue 18;
// docs/methods.md stage 7). Method 1 (ch. 1 §2.3, §4.5): the Density Condition (C1) h_C < reach_C(O)
// (Lemma 3: the Separation Condition, so the sections are joined as in O, Thm 3) and the
// Transversality Condition (C2) h_C < ½(1 − sin α_C)·reach_C(O) (Thm 15: with C1, R is homotopy
// equivalent, homeomorphic and isotopic to O). Method 2 (ch. 2 §3): the Weak Density Condition
// (C'1) h'_C < reach_e(O_C) and the Transversality Condition (C'3) h'_C < ½(1 − sin α_a)·reach(a)
// (Thm 23-24: homotopy equivalence, homeomorphism; d_H(O, R') ≤ max h'_C, Thm 20, also needs the
// Weak Transversality Condition C'2, which concerns ∂O between the planes and is not checked).
//
// Definitions written down where the thesis leaves a choice:
//  - Cells are those of all cutting planes and the six end planes (end_planes.h): the conditions are
//    checked for O inside the end planes' box, an assumption the data cannot check.
//  - h_C comes from a lattice scan (cell_scan.h) as a lower and an upper bound, made exact by the
//    cell's Chebyshev ball (cell_height.h) where the bounds straddle a critical value.
//  - Method 2: h'_C ≥ h_C (the nearest section point of x ∈ C lies on ∂C), so h_C is a lower bound
//    of h'_C; the upper bound comes from branch and bound over the cell's polytope
//    (section_cell_height.h), for the cells where it may show a condition (every prior given) and
//    the worst cells, within `section_height_cells`.
//  - α_C: the larger of the prior `max_angle_deg` and the angles measured where contours cross
//    (contour_crossings.h) on the cell's boundary. Without the prior, α_C is unknown for a cell
//    holding sections (a few measured angles do not bound it), so C2 / C'3 cannot be satisfied
//    there; measured angles still serve to show violations.
//  - The critical reach of a cell is the prior (taken as the reach's value) lowered to what the
//    data allow (the reach bounds at the cell's contour crossings and contour points,
//    contour_crossings.h and reach_bound.h). A condition is satisfied when
//    the upper bound of the height is below the critical value known for certain (every prior it
//    needs given), violated when the lower bound of the height reaches it; `violated` from the data
//    bound alone holds whatever the object (for a smooth ∂O whose sections are the contours given).
//  - Method 1's second condition is C2 or, in its place, the Intersection Condition shown on the
//    data (§4.4, intersection_condition.h): with C1 either gives Thm 14 and 16's guarantees.
//  - Cells holding no section, both methods: O ∩ ∂C is empty, so either O misses C (and so does R;
//    every condition holds there trivially: the nearest point on ∂C of any x in C is outside O), or
//    a component of O lies inside C (Prop. 2), holding a medial ball of radius ≥ reach_i. Their one
//    condition is h_C < reach_i (nothing missed), reported as both density and transversality.
//  - Observed pieces (docs/methods.md, "Observed pieces"): the cells are the Ω-cells (observed_cells.h), each
//    cell taking its Ω-cell's height and data. On an Ω-cell joining several cells (not convex) and
//    holding sections only Lemma 3 and Thm 3 hold, so only method 1's C1 may be shown there.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "geometry/arrangement/section_arrangement.h"
#include "geometry/core/named_choice.h"
#include "geometry/core/reconstruction_method.h"
#include "geometry/core/types.h"
#include "geometry/sampling/cell_scan.h"
#include "geometry/sampling/contour_crossings.h"
#include "geometry/sampling/intersection_condition.h"
#include "geometry/sampling/neighbour_angles.h"
#include "geometry/sampling/reach_bound.h"
#include "geometry/sampling/section_cell_height.h"
#include "geometry/scene/observed_piece.h"
#include "geometry/scene/section_distance_field.h"

namespace xsect {

enum class SamplingVerdict { satisfied, violated, undetermined };
constexpr std::array<NamedChoice<SamplingVerdict>, 3> kSamplingVerdicts{{
    {SamplingVerdict::satisfied, "satisfied"},
    {SamplingVerdict::violated, "violated"},
    {SamplingVerdict::undetermined, "undetermined"},
}};

/// What the user knows of the object (`sampling.*` of the configuration), mm and degrees.
struct SamplingPrior {
  std::optional<double> reach_interior_mm;  ///< reach_i (sampling.reach_interior_mm or reach_mm)
  std::optional<double> reach_exterior_mm;  ///< reach_e (sampling.reach_exterior_mm or reach_mm)
  std::optional<double> max_angle_deg;      ///< bound of α at contour points, [0, 90)
};

struct SamplingParams {
  double lattice_work = 3e8;       ///< scan budget: lattice points × planes (cell_scan.h)
  int exact_cells = 400;           ///< at most this many Chebyshev balls are solved
  CrossingParams crossings;
  ReachBoundParams reach_bounds;
  NeighbourAngleParams neighbour_angles;
  SectionHeightParams section_height;
  /// Method 2: at most this many cells get an upper bound of h'_C (section_cell_height.h), those
  /// that may be shown first, worst first; the others keep +inf (their conditions are not shown).
  int section_height_cells = 20000;
  CellTopologyParams cell_topology;
  /// Method 1: at most this many cells get their R_C sampled for the Intersection Condition (those
  /// where C1 is shown, worst first); the others are left undetermined.
  int intersection_cells = 20000;
};

/// One condition in one cell.
struct ConditionCheck {
  SamplingVerdict verdict = SamplingVerdict::undetermined;
  /// Critical value of the height, mm (+inf: unknown). The height must stay below it.
  double critical_mm = std::numeric_limits<double>::infinity();
  bool from_data = false;  ///< a violation shown by the data's reach bound alone
};

struct CellSampling {
  std::uint64_t key = 0;
  int scanned = -1;            ///< index into the scan's cells (−1: no lattice point inside)
  int arrangement_cell = -1;   ///< the arrangement's id of the cell (−1: it holds no section)
  double height_lo_mm = 0, height_hi_mm = 0;  ///< bounds of h_C (equal when exact)
  bool height_exact = false;   ///< Chebyshev ball solved
  Vec3 centre = Vec3::Zero();  ///< centre of the inscribed ball (or the lattice point reaching height_lo)
  bool end_cell = false;       ///< bounded by an end plane (an open cell closed by the end planes)
  /// Method 2 (Def. 31): an upper bound of h'_C, the largest distance of a point of C to the
  /// sections on ∂C (+inf: not bounded); its lower bound is height_lo_mm (h'_C ≥ h_C).
  double section_height_hi_mm = std::numeric_limits<double>::infinity();
  Vec3 section_farthest = Vec3::Zero();  ///< where that bound is reached (within its resolution)
  double alpha_max_deg = std::numeric_limits<double>::quiet_NaN();  ///< measured, NaN: none
  double alpha_lower_deg = 0;  ///< max over its crossings of (α measured − its margin), ≥ 0
  /// Largest α estimated from neighbouring near-parallel slices at its contour points (NaN: none);
  /// reported, never used for the verdict (neighbour_angles.h).
  double alpha_estimated_deg = std::numeric_limits<double>::quiet_NaN();
  int alpha_samples = 0;
  double interior_bound_mm = std::numeric_limits<double>::infinity();  ///< data bound of reach_i there
  double exterior_bound_mm = std::numeric_limits<double>::infinity();  ///< data bound of reach_e there
  /// min over its crossings a of ½(1 − sin α_a)·(data bound of reach(a)), mm: what C'3 may reach.
  double transversal_bound_mm = std::numeric_limits<double>::infinity();
  ConditionCheck density;        ///< C1 (method 1), C'1 (method 2); cells without sections: Prop. 2
  ConditionCheck transversality; ///< C2 / C'3
  /// Method 1: the Intersection Condition shown on the data in this cell (intersection_condition.h):
  /// `satisfied` (also for a cell without sections: S_C is empty), else `undetermined` (the data
  /// cannot show it violated: Fig. 1.11's torus and twisted cylinder have the same sections). Only
  /// checked where C1 is shown (alone it gives nothing).
  SamplingVerdict intersection = SamplingVerdict::undetermined;
  SamplingVerdict verdict = SamplingVerdict::undetermined;
  /// height / critical value of the strongest condition known for the cell (NaN: none known).
  double ratio = std::numeric_limits<double>::quiet_NaN();
  /// Observed pieces (observed_cells.h): the Ω-cell holding this cell (−1: every plane whole), how
  /// many cells of the whole planes that Ω-cell joins (met by the lattice or not), and whether one
  /// of them holds a section. The height, bounds and α above are then the Ω-cell's.
  int observed_cell = -1;
  int observed_members = 1;
  bool observed_cell_sections = false;
};

/// Whether the cell's conditions are those of a cell with sections (its Ω-cell's, with pieces).
inline bool holdsSections(const CellSampling& c) { return c.arrangement_cell >= 0 || c.observed_cell_sections; }

struct SamplingDiagnosis {
  ReconstructionMethod method = ReconstructionMethod::nearest_plane;
  SamplingPrior prior;
  CellScan scan;
  std::vector<CellSampling> cells;       ///< scanned cells in scan order, then unscanned arrangement cells
  std::vector<ContourCrossing> crossings;
  SamplingVerdict verdict = SamplingVerdict::undetermined;  ///< the topological guarantee
  SamplingVerdict density = SamplingVerdict::undetermined;  ///< over all cells
  SamplingVerdict transversality = SamplingVerdict::undetermined;
  /// Method 1: the Intersection Condition shown on the data in every cell (undetermined when
  /// not checked: method 2).
  SamplingVerdict intersection = SamplingVerdict::undetermined;
  int intersection_checked = 0;          ///< cells whose R_C was sampled (intersection_condition.h)
  int intersection_not_contractible = 0; ///< of them, R_C with a component not contractible
  int intersection_unsampled = 0;        ///< cells not sampled: too thin, no interior point found, over the budget
  std::vector<int> deciding;     ///< cells that decide the verdict, worst first (at most 20)
  int largest_empty_cell = -1;   ///< the cell without sections with the largest height (Prop. 2)
  double reach_interior_bound_mm = std::numeric_limits<double>::infinity();  ///< data, over all crossings
  double reach_exterior_bound_mm = std::numeric_limits<double>::infinity();
  int contour_points_bounded = 0;  ///< contour vertices whose balls the planes around them bound
  double alpha_max_measured_deg = std::numeric_limits<double>::quiet_NaN();
  /// α estimated from neighbouring near-parallel slices over the contour points examined, degrees.
  std::vector<double> alpha_estimates_deg;
  int exact_cells = 0;           ///< Chebyshev balls solved
  int section_height_cells = 0;  ///< method 2: cells whose h'_C was bounded from above
  /// Method 2: max over the cells with sections of the bound of h'_C (+inf when a cell has none):
  /// under C'1 and C'2 (the latter not checked), d_H(O, R') ≤ max h'_C (Thm 20).
  double section_height_max_mm = std::numeric_limits<double>::infinity();
  /// Arrangement cells that no section point keyed (not expected): when any, nothing is shown
  /// satisfied.
  int unmatched_cells = 0;
  bool prior_contradicted = false;  ///< a prior reach exceeds a data bound
  /// Observed pieces not all whole (observed_cells.h): the Ω-cells of the diagnosis' cells, those
  /// cells joined into an Ω-cell with others, and the lattice edges joining two cells through no
  /// piece. All 0 on whole planes, where the cells are the thesis' own.
  int observed_cells = 0;
  int cells_joined = 0;
  int cells_joined_with_sections = 0;  ///< of cells_joined, those whose Ω-cell holds a section
  /// Per lattice point of `scan`: D_Ω, its distance to the pieces, mm (−1 outside the box; empty
  /// on whole planes), for the slices advised on Ω-cells (observed_slice_advice.h).
  std::vector<double> observed_distance_mm;
  std::int64_t unobserved_crossings = 0;
};

/// @param planes  all cutting planes, the end planes last (SectionScene::planes), and their f_P
///                rasters (SectionScene::fields).
/// @param lo, hi  the end planes' box, mm.
/// @param voxel_mm the reconstruction's voxel (the lattice's finest spacing).
/// @param tolerance_mm how far contours may miss each other at a crossing (contour_crossings.h).
/// @param pieces  the planes' observed pieces (null, or all whole: the cells of whole planes); the
///                conditions are then checked on the Ω-cells (observed_cells.h).
SamplingDiagnosis diagnoseSampling(const std::vector<CuttingPlane>& planes,
                                   const std::vector<SectionDistanceField>& fields, const SectionArrangement& arrangement,
                                   ReconstructionMethod method, const SamplingPrior& prior, const Vec3& lo,
                                   const Vec3& hi, double voxel_mm, double tolerance_mm,
                                   const SamplingParams& params = {},
                                   const std::vector<ObservedPiece>* pieces = nullptr);

/// The thesis' consequences that the verdicts shown give, in words (e.g. "sections joined as in
/// the object (Thm 3)").
std::vector<std::string> samplingConsequences(const SamplingDiagnosis& d);

}  // namespace xsect
