// One section from several observations of one plane (issue 15, stage 3): the members of a group of
// coincident planes (geometry/coincident_planes.h) become one cutting plane whose sections are the
// consensus of theirs, and the disagreement between them is measured.
//
// Consensus: the region where the median of the members' signed distances to their contours is
// negative (the median over the members that observed each point; a point no member observed is
// outside). For two observations the median is the mean: the region halfway between their
// contours. For more it is robust: a minority of observations that missed the section (empty, or
// wrong) does not move it. It is sampled on a raster of the finest member pixel (1/1024 of the
// extent's diagonal for contours without pixels) in the first member's plane, with signed
// distances exact within 1.5 times the largest gap between the members' contours (at least 16
// raster steps; farther, every member agrees on the sign), and traced at sub-raster precision
// (segmentation/iso_contours.h).
#pragma once

#include <vector>

#include "geometry/coincident_planes.h"
#include "geometry/types.h"

namespace xsect {

struct CoincidentConsensus {
  CoincidentGroup group;
  std::vector<int> slices;            ///< the members' CuttingPlane::slice, in member order
  double disagreement_area_mm2 = 0;   ///< area where all members observed and their sections differ
  double max_correction_mm = 0;       ///< largest distance from a member's contour to the consensus'
};

struct CoincidentMerge {
  std::vector<CuttingPlane> planes;               ///< each group replaced by its first member, carrying the consensus
  std::vector<std::vector<Section>> labelled;     ///< per-label sections kept in step (empty if given empty)
  std::vector<CoincidentConsensus> consensus;     ///< one per group, in the order of coincidentGroups
};

/// Replaces every group of coincident planes by one plane: the first member's plane, observed where
/// any member observed (extent: the bounding rectangle; field of view: their union when it is not the
/// whole rectangle), with the consensus of the members' sections (and of each label's sections).
/// @param planes    segmented slices or .csl planes (no virtual planes).
/// @param labelled  per plane, each label's sections, or empty.
CoincidentMerge mergeCoincidentPlanes(std::vector<CuttingPlane> planes,
                                      std::vector<std::vector<Section>> labelled);

}  // namespace xsect
