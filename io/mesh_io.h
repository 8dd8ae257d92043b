// Triangle mesh files: binary PLY, binary STL, OBJ (write), and the same three (read).
#pragma once

#include <string>

#include "geometry/core/types.h"

namespace xsect {

/// Format from the extension: "ply", "stl" or "obj". Throws InputError otherwise.
void writeMesh(const std::string& path, const TriangleMesh& mesh);
/// Reads ASCII or binary PLY/STL and OBJ; STL vertices are welded (exact duplicates merged).
/// Throws InputError naming the file on malformed input.
TriangleMesh readMesh(const std::string& path);

}  // namespace xsect
