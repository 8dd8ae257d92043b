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

/// A smooth field's zero set as an OpenVDB narrow-band level set and its mesh.
struct LevelSetSurface {
  NarrowBandLevelSet level_set;  ///< signed distance to the zero set, mm, on the field's lattice
  TriangleMesh mesh;             ///< the level set's zero set (OpenVDB volumeToMesh)
};

/// Renormalises the zero set of `field` (any continuous field, negative inside, not necessarily a
/// distance) to a signed distance in a narrow band (OpenVDB tools::levelSetRebuild: the zero set is
/// polygonised, then the exact distance to it is computed within the band) and meshes it.
/// @param half_width_voxels  band half-width on each side (>= 1).
/// @param adaptivity         OpenVDB's mesh adaptivity in [0, 1] (0 = one vertex per surface voxel).
LevelSetSurface levelSetSurface(const ScalarField& field, double half_width_voxels = 3.0,
                                double adaptivity = 0.0);

}  // namespace xsect
