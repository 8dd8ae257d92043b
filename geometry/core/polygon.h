// Planar polygon measures on rings and sections (plane coordinates, mm): signed area (positive =
// counter-clockwise), containment (crossing number), and the exact signed distance to a set of
// sections (negative inside), the f_i of thesis ch. 1 §1.1 evaluated from the polygons.
#pragma once

#include <vector>

#include "geometry/core/types.h"

namespace xsect {

double signedArea(const Ring& ring);
/// Length of a closed ring, mm.
double ringLength(const Ring& ring);
/// Axis-aligned bounds of a ring's vertices (of a section: of its outer ring).
Eigen::AlignedBox2d ringBounds(const Ring& ring);

/// The sections' bounds in plane coordinates (mm): a contour file's observed extent; a zero
/// rectangle without sections.
PlaneRect sectionBounds(const std::vector<Section>& sections);
/// Area of a section: outer minus holes, mm².
double sectionArea(const Section& s);
/// Point strictly inside the ring (even-odd crossing rule; boundary points undecided).
bool ringContains(const Ring& ring, const Vec2& p);
bool sectionContains(const Section& s, const Vec2& p);
/// The point of segment [a, b] nearest to p (a when a = b).
Vec2 nearestOnSegment(const Vec2& p, const Vec2& a, const Vec2& b);
/// Three points collinear up to rounding: twice the triangle's area at most 1e-9 of its longest
/// edge squared (contour samples of a straight stretch; a "triangle" of them has no inside).
bool isSliverTriangle(const Vec2& a, const Vec2& b, const Vec2& c);
/// Distance from p to the nearest edge of the ring, mm.
double ringDistance(const Ring& ring, const Vec2& p);
/// Exact signed distance from p to the boundary of the union of the sections; negative inside.
/// Brute force over all edges: the reference for section_distance_field.h's rasters.
double signedDistanceToSections(const std::vector<Section>& sections, const Vec2& p);
/// Sections from loose rings: outer rings oriented counter-clockwise, holes clockwise, each hole
/// attached to the smallest outer ring that contains it (islands inside holes are outer rings of
/// their own; a hole may touch its outer ring at vertices). Holes contained in no outer ring are
/// dropped.
std::vector<Section> sectionsFromRings(std::vector<Ring> outers, std::vector<Ring> holes);
/// Centroid of a section (area-weighted, holes subtracted).
Vec2 sectionCentroid(const Section& s);
/// Points along every ring (outer rings and holes) of the sections: each vertex, and points on
/// each edge at most `step` mm apart (step = +inf: the vertices only), ring by ring in order.
std::vector<Vec2> contourSamples(const std::vector<Section>& sections, double step);

}  // namespace xsect
