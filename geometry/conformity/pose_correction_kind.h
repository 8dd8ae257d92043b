// Which pose corrections stage 3 estimates from the sections' disagreement along their common
// lines (`conformity.pose_correction`; geometry/conformity/pose_correction.h).
#pragma once

#include "geometry/core/named_choice.h"

namespace xsect {

enum class PoseCorrectionKind {
  none,         ///< the recorded poses are used as they are
  translation,  ///< one translation per slice (3 degrees of freedom)
  rigid,        ///< one rotation and translation per slice (6 degrees of freedom)
};
constexpr std::array<NamedChoice<PoseCorrectionKind>, 3> kPoseCorrectionKinds{{
    {PoseCorrectionKind::none, "none"},
    {PoseCorrectionKind::translation, "translation"},
    {PoseCorrectionKind::rigid, "rigid"},
}};

}  // namespace xsect
