// A mesh against the solid it bounds (see mesh_bounds.h).
#include "pipeline/mesh_bounds.h"

#include <stdexcept>

namespace xsect {

std::string bettiText(const Betti& b) {
  return "(" + std::to_string(b[0]) + ", " + std::to_string(b[1]) + ", " + std::to_string(b[2]) + ")";
}

void requireMeshBoundsSolid(const MeshTopology& mesh, const Betti& solid, const std::string& what) {
  if (solid[0] == 0 || mesh.betti[0] == 0)
    throw std::runtime_error(what + " is empty although the sections are not (the solid has " +
                             std::to_string(solid[0]) + " components): nothing written");
  if (mesh.watertight && mesh.betti == solid) return;
  throw std::runtime_error(what + " has Betti numbers " + bettiText(mesh.betti) +
                           (mesh.watertight ? "" : " and is not watertight") + " while the voxel solid it was made from has " +
                           bettiText(solid) + "; nothing written (a defect of xsect: please report it with the configuration)");
}

}  // namespace xsect
