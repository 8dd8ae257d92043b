// Cutting planes that observe one plane (issue 15): the same plane imaged twice (a frame exported
// twice with different segmentations, two sweeps through one position, two contours on one plane
// of a .csl). The thesis' planes are distinct (ch. 1 §1.1: the sections of O by n distinct planes);
// two observations of one plane must become one section before the arrangement is built, so they
// are found here and stage 3 replaces each group by a consensus (segmentation/coincident_consensus.h).
//
// Definition. Planes A and B coincide when their normals make an angle below 1 degree and every
// corner of each one's observed extent (the image rectangle; the sections' bounds for .csl planes)
// lies within `tolerance` of the other plane, where tolerance is a thousandth of the finer pixel of
// the two or, for contours given without pixels, a millionth of the larger of the extents' diagonal
// and their corners' largest coordinate (the rounding of coordinates written as text): the
// same plane up to the rounding of a pose, never two frames of a sweep (even a dense sweep's frames
// are hundredths of a pixel apart at least). A plane that observed nothing (an empty extent)
// coincides with none.
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct CoincidentGroup {
  std::vector<std::size_t> members;  ///< indices into the planes, ascending (at least two)
  double max_offset_mm = 0.0;        ///< largest distance of a member's extent corner to the first's plane, or of the first's to the member's
  double max_angle_deg = 0.0;        ///< largest angle between a member's normal and the first's
};

/// The distance below which planes a and b count as one (see the file comment), mm.
double coincidenceTolerance(const CuttingPlane& a, const CuttingPlane& b);

/// Whether a and b coincide (see the file comment); virtual planes never do.
bool planesCoincide(const CuttingPlane& a, const CuttingPlane& b);

/// Groups of coincident planes, each group's members coinciding with its first member (the lowest
/// index); planes that coincide with no other are in no group. Deterministic: groups in the order of
/// their first member.
std::vector<CoincidentGroup> coincidentGroups(const std::vector<CuttingPlane>& planes);

}  // namespace xsect
