// The check behind "one solid" (issue 14, issue 49): a mesh written must bound the solid that
// report.json describes, with its Betti numbers and watertight; a difference is a defect of xsect,
// an error (exit 1, nothing written), never a warning. Read by the mesh stage (smoothed surface,
// materials) and by the methods (pipeline/methods/) for their own meshes.
#pragma once

#include <string>

#include "geometry/core/digital_topology.h"
#include "geometry/meshing/mesh_topology.h"

namespace xsect {

/// "(b0, b1, b2)".
std::string bettiText(const Betti& b);

/// Throws std::runtime_error naming `what` unless `mesh` is watertight, non-empty and has the Betti
/// numbers `solid` of the voxel solid it was made from.
void requireMeshBoundsSolid(const MeshTopology& mesh, const Betti& solid, const std::string& what);

}  // namespace xsect
