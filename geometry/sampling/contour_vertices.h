// The contour vertices of the real planes' sections among an arrangement's points, evenly thinned
// to at most a given count: the points where the sampling diagnosis (issue 18) measures the surface
// (reach_bound.h, neighbour_angles.h).
#pragma once

#include <algorithm>
#include <vector>

#include "geometry/arrangement/section_arrangement.h"

namespace xsect {

/// Indices into arrangement.points of every stride-th contour vertex of a real plane, so that at
/// most `max_points` (≥ 1) remain. Deterministic.
inline std::vector<int> spreadContourVertices(const std::vector<CuttingPlane>& planes,
                                              const SectionArrangement& arrangement, std::size_t max_points) {
  std::vector<int> vertices;
  for (std::size_t i = 0; i < arrangement.points.size(); ++i) {
    const SectionPoint& s = arrangement.points[i];
    if (s.kind == SectionPoint::vertex && !planes[std::size_t(s.plane)].is_virtual) vertices.push_back(int(i));
  }
  const std::size_t keep = std::max<std::size_t>(max_points, 1);
  const std::size_t stride = std::max<std::size_t>(1, (vertices.size() + keep - 1) / keep);
  std::vector<int> out;
  for (std::size_t i = 0; i < vertices.size(); i += stride) out.push_back(vertices[i]);
  return out;
}

}  // namespace xsect
