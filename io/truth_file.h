// truth.yaml: the analytic shape a phantom was rendered from, its Betti numbers and its reach.
#pragma once

#include <string>

#include "geometry/phantom_shape.h"

namespace xsect {

void writeTruthFile(const std::string& path, const PhantomShape& shape);
/// Throws InputError naming the file and key on malformed input.
PhantomShape readTruthFile(const std::string& path);

}  // namespace xsect
