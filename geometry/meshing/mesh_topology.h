// Topology of a triangle mesh taken as the boundary of a solid: closedness (watertight, edge
// manifold, consistently oriented) and the Betti numbers of the solid it bounds.
#pragma once

#include "geometry/core/types.h"

namespace xsect {

struct MeshTopology {
  bool watertight = false;   ///< every edge shared by exactly two triangles, opposite directions
  int surfaces = 0;          ///< connected components of the surface
  Betti betti{0, 0, 0};      ///< of the solid: b0 = outer surfaces, b1 = total genus, b2 = cavity surfaces
  double volume_mm3 = 0.0;   ///< enclosed signed volume
};

/// b0 counts surface components with positive enclosed volume (outer boundaries), b2 those with
/// negative volume (cavity boundaries, outward normals point into the cavity), b1 the sum of the
/// genera g = 1 - chi/2 of all components (for a solid in R^3, b1 = total genus of its boundary).
MeshTopology meshTopology(const TriangleMesh& mesh);

}  // namespace xsect
