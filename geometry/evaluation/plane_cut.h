// The intersection of a triangle mesh with a plane as 2D segments in the plane's (u, v) frame,
// and the agreement (intersection over union) between the region those segments enclose and a
// set of sections, measured on scan lines.
#pragma once

#include <array>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// A segment of the cut, endpoints in plane coordinates (mm).
using Segment2 = std::array<Vec2, 2>;

/// Segments where the plane crosses the mesh's triangles. A vertex exactly on the plane counts as
/// lying on the normal's side (symbolic perturbation), so every triangle contributes zero or one
/// segment and a closed mesh yields closed loops; endpoints shared by two triangles are computed
/// identically in both (from the edge with its endpoints in index order).
/// @param mesh  triangle mesh, world mm
/// @param plane cutting plane with its (u, v) frame
std::vector<Segment2> cutMesh(const TriangleMesh& mesh, const Plane& plane);

/// Intersection over union of region A, enclosed by `cut` (even-odd rule), and region B, the
/// union of `sections` (outer rings minus holes, even-odd over all rings).
/// Measured on horizontal scan lines (constant v) spaced `resolution_mm` apart, at pixel-centre
/// heights of a raster covering the union of both regions' bounds (clipped to `clip` when given);
/// along each line the inside intervals are measured exactly. Returns NaN when the union is empty
/// (both regions empty within the clip).
/// @param resolution_mm scan-line spacing, mm (> 0, std::invalid_argument otherwise)
/// @param clip          optional observed rectangle in plane coordinates (mm)
double regionIoU(const std::vector<Segment2>& cut, const std::vector<Section>& sections,
                 double resolution_mm, const PlaneRect* clip = nullptr);

/// Area (mm²) enclosed by `cut` (even-odd), on the same scan lines as regionIoU.
double cutArea(const std::vector<Segment2>& cut, double resolution_mm);

}  // namespace xsect
