// .csl cross-section files (OReX / "CSLC"): planes A x + B y + C z + D = 0 with closed contours
// of 3D vertices; 'h' marks holes. Read directly into cutting planes with sections.
#pragma once

#include <string>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// Each plane's frame: normal (A, B, C) normalised, origin at the mean of its vertices (their
/// projection defines the plane: the file's D is not trusted), u, v completing a right-handed frame.
/// A plane with no vertex is an empty section; its offset is the file's D, with the sign that
/// puts the plane nearer the other planes' vertices. Contour orientation is normalised
/// (outer counter-clockwise, holes clockwise). Labels are ignored (one material).
/// Contours are cleaned of repeated vertices; a ring without area (a point or a segment: the
/// section of a tangent plane) is dropped with a warning naming its plane and component. With
/// `repair` (input.repair_contours, the default), rings of a plane that cross themselves or each
/// other, or touch, are made simple rings of the same region (geometry/core/ring_repair.h: the
/// positive winding of the oriented lobes; 'h' rings are holes), with a warning naming the plane,
/// its rings and the area before and after; without, a self-intersecting ring is an error naming
/// them (geometry/core/ring_validity.h).
/// Throws InputError naming the file, line and field on malformed content.
std::vector<CuttingPlane> readCslFile(const std::string& path, std::vector<std::string>* warnings = nullptr,
                                      bool repair = true);

/// Writes planes and their sections as .csl (the layout readCslFile reads and OReX writes): per
/// plane its normalised equation A x + B y + C z + D = 0, the contour vertices in world mm, one
/// component per ring (outer rings label 1, holes marked 'h'). Numbers with 17 significant digits.
void writeCslFile(const std::string& path, const std::vector<CuttingPlane>& planes);

}  // namespace xsect
