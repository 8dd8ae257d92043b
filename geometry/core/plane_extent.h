// `reconstruction.planes`: how far a cutting plane cuts space (issue 20). The thesis' planes are
// whole planes; a tracked image observed only its piece of the plane (image rectangle ∩ field of
// view). With `observed`, every definition that reads "the cutting plane P" reads "the observed
// piece of P" instead (docs/methods.md, "Observed pieces"); with every piece a whole plane both agree.
#pragma once

#include "geometry/core/named_choice.h"

namespace xsect {

enum class PlaneExtent {
  observed,  ///< a slice cuts space only where it was observed (images, PLUS sequences)
  whole      ///< a slice's plane cuts all of space (the thesis; .csl and .contour inputs)
};
constexpr std::array<NamedChoice<PlaneExtent>, 2> kPlaneExtents{{
    {PlaneExtent::observed, "observed"},
    {PlaneExtent::whole, "whole"},
}};

}  // namespace xsect
