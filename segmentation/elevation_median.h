// The elevation median of a sweep (segmentation.elevation_median_mm; issue 49, item 3): each
// frame's sections become the median of its own and its two neighbours' in the input's order.
//
// Why: an ultrasound frame is a slab as thick as the beam's elevational width (about a millimetre),
// so frames closer than that see nearly the same tissue, while the speckle that joins a dark lumen
// to dark tissue beside it (bulges of 1-3 mm, segment_slice.h's core) changes from frame to frame.
// Measured on bench/ultrasound_family.py: every bulge that set the Hausdorff distance lay in one
// frame's slab (0.3-0.4 mm thick along the sweep), its neighbours' contours on the truth.
//
// Definition. For frame k with neighbours k-1 and k+1, let d_m(x) be the signed distance (mm,
// negative inside) at a point x of plane k to frame m's sections projected orthogonally on plane k.
// Where both neighbours and the frame observed x (image rectangle and field of view), both
// neighbours' planes pass within `max_mm` of x and make an angle of at most 10° with plane k, the
// frame's region is {median(d_{k-1}, d_k, d_{k+1}) < 0}; elsewhere it is {d_k < 0}, its own. So:
//  - a surface that grows or shrinks monotonically from frame to frame (d_k between its
//    neighbours' values at x) keeps the frame's own contour there;
//  - what one frame of three saw alone (a bulge, a speck, a pinhole) goes, and what both
//    neighbours saw and the frame missed comes;
//  - a structure thinner than two frame spacings along the sweep loses its middle frame's section.
// Every frame is computed from the input's sections (a median filter, not an iteration). The first
// and last frames, and frames whose neighbours are far, tilted or elsewhere, keep their own. A frame
// whose region does not change at any raster node keeps its contours as they were; a changed one
// is traced again from the median's field on a raster of its pixel (section_raster.h).
#pragma once

#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct ElevationMedian {
  std::vector<CuttingPlane> planes;  ///< the input's planes, sections replaced where the median changed them
  int frames_changed = 0;            ///< frames whose region changed
  double area_removed_mm2 = 0;       ///< total area the median took from frames' regions (raster nodes × step²)
  double area_added_mm2 = 0;         ///< total area it added
};

/// @param planes  a series' segmented frames in acquisition order (slices.yaml's or the recording's),
///                one material (label sections are not filtered).
/// @param max_mm  the farthest a neighbour's plane may lie from a point of the frame to vote there
///                (mm, > 0; the beam's elevational half-width is a natural value).
ElevationMedian elevationMedian(std::vector<CuttingPlane> planes, double max_mm);

}  // namespace xsect
