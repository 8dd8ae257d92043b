// One section from several observations of one plane (issue 15, stage 3): the members of a group of
// coincident planes (geometry/arrangement/coincident_planes.h) become one cutting plane whose sections are the
// consensus of theirs, and the disagreement between them is measured.
//
// Consensus. Let d_m be member m's signed distance to its contours (negative inside), taken where
// m observed the plane (its image rectangle and field of view). Members holding no section do not
// vote unless none holds one: a plane observed again without its section does not erase it (the
// same rule as geometry/reconstruction/plane_evidence.h). Then
//  - images (slices): the region where the median of the voting d_m is negative. For two members the
//    median is their mean: the region halfway between their contours; for more it is robust, a
//    minority that saw the section wrongly does not move it;
//  - contours given directly (.csl, observed everywhere): the region where the least d_m is
//    negative, the union of the members' sections: a file that lists a plane twice lists more of
//    its contours.
// The d_m are sampled on a raster of the finest member pixel (1/1024 of the sections' extent for
// contours without pixels) in the first member's plane: exact within 16 raster steps of a contour,
// and beyond from an exact Euclidean distance transform of the raster, so that the median of
// members far from each other's contours is still decided by distances, never by a clamp. The
// region is traced at sub-raster precision (segmentation/iso_contours.h); when every voting member
// holds the same contours, the first member's are kept as they are. Labelled (per-material)
// sections are merged label by label on the same raster and traced together so that they tile the
// plane (labelIsoContours); the union then becomes the merged plane's sections.
#pragma once

#include <string>
#include <vector>

#include "geometry/arrangement/coincident_planes.h"
#include "geometry/core/types.h"

namespace xsect {

struct CoincidentConsensus {
  CoincidentGroup group;
  std::vector<int> slices;            ///< the members' CuttingPlane::slice, in member order
  int voting = 0;                     ///< members holding sections (or all, when none does)
  /// How the sections were merged: "median" (images), "union" (.csl), "identical" (the voters held
  /// the same contours, kept as they are).
  std::string rule = "median";
  double disagreement_area_mm2 = 0;   ///< area where every member observed and the voters differ
  double max_correction_mm = 0;       ///< largest distance from a voter's contour to the consensus'
};

struct CoincidentMerge {
  std::vector<CuttingPlane> planes;               ///< each group replaced by its first member, carrying the consensus
  std::vector<std::vector<Section>> labelled;     ///< per-label sections kept in step (empty if given empty)
  std::vector<CoincidentConsensus> consensus;     ///< one per group, in the order of coincidentGroups
};

/// Replaces every group of coincident planes by one plane: the first member's plane, with the
/// consensus of the members' sections (and of each label's), observed where any member observed
/// (the first member's extent and field of view when all observed the same region; otherwise the
/// bounding rectangle of their extents and, as field of view, the union of their observed regions).
/// @param planes    segmented slices or .csl planes (no virtual planes).
/// @param labelled  per plane, each label's sections, or empty. Throws std::invalid_argument if it
///                  is neither empty nor one row per plane.
CoincidentMerge mergeCoincidentPlanes(std::vector<CuttingPlane> planes,
                                      std::vector<std::vector<Section>> labelled);

}  // namespace xsect
