// Meshing the zero level of a sampled field with OpenVDB (tools::volumeToMesh): a closed triangle
// mesh with outward normals where the sampled solid {value < 0} is well-composed and away from the
// grid border.
#pragma once

#include "geometry/core/block_grid.h"
#include "geometry/core/types.h"

namespace xsect {

/// @param field       dense samples, negative inside; the outermost layer of voxels should be
///                    outside so the surface closes.
/// @param adaptivity  OpenVDB's adaptivity in [0, 1] (0 = one vertex per surface voxel).
/// Quads are split along their shorter diagonal; faces oriented so that the enclosed volume is
/// positive (outward normals).
TriangleMesh meshZeroLevel(const ScalarField& field, double adaptivity = 0.0);
/// The same for a field stored by blocks: its tiles become OpenVDB tiles, its leaves leaves, so
/// the cost follows the leaves. The mesh is the one the dense field with these values gives.
TriangleMesh meshZeroLevel(const BlockGrid<float>& field, double adaptivity = 0.0);

/// A smooth field's zero set as an OpenVDB narrow-band level set and its mesh.
struct LevelSetSurface {
  NarrowBandLevelSet level_set;  ///< distance to `mesh`, mm, signed by the field, on its lattice
  TriangleMesh mesh;             ///< the field's zero set (OpenVDB volumeToMesh)
};

/// The zero set of `field` (any continuous field, negative inside, not necessarily a distance) as a
/// mesh (meshZeroLevel) and as a narrow-band level set with the same solid: within
/// half_width_voxels of the mesh, the distance to the mesh (OpenVDB
/// tools::meshToUnsignedDistanceField) with the sign of the field at that voxel. Give a field
/// whose solid {value < 0} is well-composed (digital_topology.h makeWellComposed) and whose
/// outermost voxel layer is outside: the mesh then bounds that solid and has its Betti numbers.
/// @param half_width_voxels  band half-width on each side (>= 1).
/// @param adaptivity         OpenVDB's mesh adaptivity in [0, 1] (0 = one vertex per surface voxel).
LevelSetSurface levelSetSurface(const ScalarField& field, double half_width_voxels = 3.0,
                                double adaptivity = 0.0);

}  // namespace xsect
