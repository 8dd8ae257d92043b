// Open ends of the data (docs/methods.md, "end planes"): the slices whose sections lie beyond every
// other slice's sections along their plane's normal. There the object is cut open by the
// outermost slice and no slice saw where it ends: every method closes such ends by the virtual
// empty planes of end_planes.h, end_margin_mm beyond the sections' bounds, and the solid between
// is an extrapolation. A multi-axial stack has none (the other stacks' sections reach past each
// stack's outermost plane); a parallel stack or a sweep through a longer object has two.
#pragma once

#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// The slice numbers of the real planes of `planes` that hold sections and that no other plane's
/// section vertex passes by more than `tolerance_mm` on one side (the side their normal points to,
/// or the other), in the order of `planes`. Cost: each plane against the others' section bounds,
/// the vertices of a plane read only where its bounds reach past (so a plane with a larger section
/// beside it is decided after a few planes).
std::vector<int> openEndSlices(const std::vector<CuttingPlane>& planes, double tolerance_mm);

}  // namespace xsect
