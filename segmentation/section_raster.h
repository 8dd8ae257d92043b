// Sections of several planes sampled in one plane's frame: the raster that the consensus of
// coincident observations (coincident_consensus.h) and the elevation median of a sweep
// (elevation_median.h) vote on. Points of another plane map to the reference plane through the
// world (orthogonal projection); the signed distance to a plane's sections (mm, negative inside)
// is exact within kBandSteps raster steps of a contour and beyond from a Euclidean distance
// transform of the raster, so that values far from the contours still order the planes; the
// region a vote keeps is traced back at sub-raster precision (iso_contours.h).
#pragma once

#include <array>
#include <opencv2/core.hpp>
#include <vector>

#include <Eigen/Geometry>

#include "geometry/core/types.h"

namespace xsect {

/// Distances are exact within this many raster steps of a contour.
constexpr double kSectionRasterBandSteps = 16.0;

/// Nodes origin + step * (i, j), i < nu, j < nv, in the reference plane's coordinates (mm).
struct SectionRaster {
  Vec2 origin = Vec2::Zero();
  double step = 1.0;
  int nu = 0, nv = 0;
  Vec2 node(int i, int j) const { return origin + step * Vec2(i, j); }
  double count() const { return double(nu) * double(nv); }
  /// q as fixed-point raster coordinates for cv::fillPoly with kSectionRasterShift bits.
  cv::Point fixedPoint(const Vec2& q) const;
};

/// Fixed-point bits of the polygons given to cv::fillPoly.
constexpr int kSectionRasterShift = 8;

/// A raster over `box` grown by a margin of 18 steps, of step `step` (mm) or coarser: at most
/// `maxNodes` nodes, and at most 6.4e7 distances (256 MB) for `layers` values per node. Nodes
/// lie on multiples of the step. Throws std::runtime_error if no step fits.
SectionRaster sectionRasterAround(const Eigen::AlignedBox2d& box, double step, int layers, double maxNodes);

/// `member`'s point p in `reference`'s plane coordinates (through the world).
Vec2 inReferenceFrame(const CuttingPlane& reference, const CuttingPlane& member, const Vec2& p);

/// `member`'s ring in `reference`'s frame. A member seen from the other side (opposite normal)
/// maps by a reflection: its rings are reversed to keep outer rings counter-clockwise.
Ring ringInReferenceFrame(const CuttingPlane& reference, const CuttingPlane& member, Ring ring);

/// `member`'s sections in `reference`'s frame (ringInReferenceFrame on every ring).
std::vector<Section> sectionsInReferenceFrame(const CuttingPlane& reference, const CuttingPlane& member,
                                              std::vector<Section> sections);

/// The extent's corners, counter-clockwise from its least one.
std::array<Vec2, 4> extentCorners(const PlaneRect& e);

/// Whether the extent is empty (nothing observed).
bool extentIsEmpty(const PlaneRect& e);

/// 1 where `member` observed the plane, on the raster of `reference`'s frame: its image rectangle,
/// narrowed by its field of view (even-odd, as geometry/arrangement/section_traces.cpp reads it).
cv::Mat observedMask(const CuttingPlane& reference, const CuttingPlane& member, const SectionRaster& r);

/// The signed distance (mm, negative inside; CV_32F, row j, column i) to `sections` at every node:
/// exact within kSectionRasterBandSteps steps of a contour, beyond it from a Euclidean distance
/// transform between inside and outside nodes (never less than the band). No section: the band
/// everywhere.
cv::Mat signedDistanceOnRaster(const std::vector<Section>& sections, const SectionRaster& r);

/// The signed distance to `sections` exact within `band_steps` raster steps of a contour and ±that
/// band beyond (only the sign): all a vote of signs needs, at the cost of the contours' length times
/// the band's area, not the raster's.
cv::Mat signedDistanceNearContours(const std::vector<Section>& sections, const SectionRaster& r, double band_steps);

/// Rings of isoContours (raster coordinates) as plane coordinates, split into sections of `label`.
std::vector<Section> sectionsOfRasterRings(std::vector<Ring> rings, const SectionRaster& r, int label);

}  // namespace xsect
