// Method 3's solid R'' as its tetrahedra (thesis ch. 3 §1-2, delaunay_reconstruction.h): a table of
// vertices (the section-vertices, world coordinates, mm) and four vertex ids per tetrahedron.
// Shared vertices are stored once: D3 over 11 500 cells of multiaxial-3x40 is 1.09 M tetrahedra on
// 0.5 M vertices, 105 MB as four positions per tetrahedron and 29 MB as this.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct TetrahedronSet {
  std::vector<Vec3> vertices;                ///< positions, mm
  std::vector<std::array<int, 4>> corners;   ///< per tetrahedron, four ids into `vertices`

  std::size_t size() const { return corners.size(); }
  bool empty() const { return corners.empty(); }
  /// Tetrahedron t's four vertices.
  std::array<Vec3, 4> at(std::size_t t) const {
    const std::array<int, 4>& c = corners[t];
    return {vertices[std::size_t(c[0])], vertices[std::size_t(c[1])], vertices[std::size_t(c[2])],
            vertices[std::size_t(c[3])]};
  }
  bool operator==(const TetrahedronSet& o) const { return vertices == o.vertices && corners == o.corners; }
};

}  // namespace xsect
