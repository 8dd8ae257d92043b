// Meshing the zero level of a sampled field with OpenVDB (tools::volumeToMesh): a closed triangle
// mesh with outward normals where the sampled solid {value < 0} is well-composed and away from the
// grid border.
#pragma once

#include "geometry/types.h"

namespace xsect {

/// @param field       dense samples, negative inside; the outermost layer of voxels should be
///                    outside so the surface closes.
/// @param adaptivity  OpenVDB's adaptivity in [0, 1] (0 = one vertex per surface voxel).
/// Quads are split along their shorter diagonal; faces oriented so that the enclosed volume is
/// positive (outward normals).
TriangleMesh meshZeroLevel(const ScalarField& field, double adaptivity = 0.0);

}  // namespace xsect
