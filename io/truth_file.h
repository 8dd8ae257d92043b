// truth.yaml: the analytic shape a phantom was rendered from, its Betti numbers (and those of each
// material of a two-label phantom) and its reach (interior, exterior and their minimum).
#pragma once

#include <string>

#include "geometry/phantoms/phantom_shape.h"

namespace xsect {

/// Computes the per-label Betti numbers (labelBettiNumbers) unless shape.label_betti is set.
void writeTruthFile(const std::string& path, const PhantomShape& shape);
/// Throws InputError naming the file and key on malformed input. The optional keys of newer
/// files (reach_interior_mm, reach_exterior_mm, labels, shape.label_split, shape.params.blend_mm)
/// fill the corresponding PhantomShape fields; a vessel tree without blend_mm is the plain union
/// of its capsules (blend_mm = 0), as files written before blending existed describe.
PhantomShape readTruthFile(const std::string& path);

}  // namespace xsect
