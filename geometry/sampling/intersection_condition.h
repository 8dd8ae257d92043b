// The Intersection Condition (thesis ch. 1 §4.4, Def. 25) shown on the data, per cell, for
// method 1. The thesis' sufficient form (§4.4): every connected component of lift(S_C) is
// contractible. Then π1(lift(S_C)) is trivial and the lift map L_* is onto (Def. 25 holds: under
// the Separation Condition the sections whose lifts meet are joined in M_C, and every loop is
// trivial), so with the Separation Condition R is homotopy equivalent (Thm 12, 14), homeomorphic
// and isotopic (Thm 16) to O.
//
// lift(S_C) is checked through R_C, the reconstruction within the cell, which is homotopy
// equivalent to it (§4.4: R_C deformation retracts on lift(S_C) along the segments [x, lift(x)]):
//     R_C = {x ∈ C : np(x), x's nearest point of ∂C, lies in a section},
// np(x) being x's projection on its nearest plane of C (C convex). R_C is sampled on a lattice of
// the cell's box along its principal axes, at the reconstruction's voxel size (finer for a small
// cell; at least 4 layers along every axis, an even number so that no layer lies on the bisector
// of two parallel facets), and the Betti numbers of the union of the closed lattice cubes whose
// centres lie in R_C are computed (voxelBetti): the components are contractible when b1 = b2 = 0.
// Like the reconstruction itself this holds at the voxel's resolution (a handle or a gap thinner
// than it can be missed). A cell holding fewer than `min_inside` lattice points, or whose lattice
// meets no point of R_C although the cell holds sections, is sampled again 4 times finer; if it
// still does, or its lattice would exceed `max_points`, nothing is shown there.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/core/types.h"
#include "geometry/scene/section_distance_field.h"

namespace xsect {

struct CellReconstructionTopology {
  bool sampled = false;     ///< the cell was built and held enough lattice points
  Betti betti{0, 0, 0};     ///< of R_C's sampling
  int points_inside = 0;    ///< lattice points in C
  /// The Intersection Condition shown: every component of R_C (≃ lift(S_C)) contractible.
  bool contractible() const { return sampled && betti[1] == 0 && betti[2] == 0; }
};

struct CellTopologyParams {
  /// The lattice's largest spacing, mm (the reconstruction's voxel: the check resolves what the
  /// reconstruction does); 0: none.
  double max_spacing_mm = 0;
  int min_points = 2048;       ///< a smaller cell gets about this many points over its box
  int min_inside = 64;         ///< fewer lattice points inside the cell: not sampled
  std::int64_t max_points = 4000000;  ///< a larger lattice is not sampled (nothing shown)
};

/// @param planes  all planes (unit normals) and their f_P rasters (section_distance_field.h), one
///                per plane (a plane without a raster holds no section).
/// @param sides   the cell's side of each plane (+1: the normal's side).
/// @param interior a point strictly inside the cell, mm.
/// @param lo, hi  a box that closes the cell (the end planes' box, padded), mm.
CellReconstructionTopology cellReconstructionTopology(const std::vector<Plane>& planes,
                                                      const std::vector<SectionDistanceField>& fields,
                                                      const std::vector<int>& sides, const Vec3& interior,
                                                      const Vec3& lo, const Vec3& hi,
                                                      const CellTopologyParams& params = {});

}  // namespace xsect
