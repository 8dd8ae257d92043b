// The reconstruction methods of the thesis: `reconstruction.method` of the configuration.
#pragma once

#include "geometry/core/named_choice.h"

namespace xsect {

enum class ReconstructionMethod {
  nearest_plane,    ///< method 1 (thesis ch. 1, Def. 16): R
  section_voronoi,  ///< method 2 (thesis ch. 2, Def. 28): R', with thickened planes
  delaunay          ///< method 3 (thesis ch. 3): R'', the pruned Delaunay triangulation of the sections
};
constexpr std::array<NamedChoice<ReconstructionMethod>, 3> kReconstructionMethods{{
    {ReconstructionMethod::nearest_plane, "nearest_plane"},
    {ReconstructionMethod::section_voronoi, "section_voronoi"},
    {ReconstructionMethod::delaunay, "delaunay"},
}};

/// The method's number in the thesis' order (1, 2, 3).
constexpr int methodNumber(ReconstructionMethod m) { return int(m) + 1; }
static_assert(methodNumber(ReconstructionMethod::nearest_plane) == 1 &&
              methodNumber(ReconstructionMethod::section_voronoi) == 2 &&
              methodNumber(ReconstructionMethod::delaunay) == 3);

}  // namespace xsect
