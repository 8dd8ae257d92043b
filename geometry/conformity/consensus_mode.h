// How two traces of one common line are made to agree (conformity, thesis Introduction §3.1):
// `conformity.mode` of the configuration.
#pragma once

#include "geometry/core/named_choice.h"

namespace xsect {

enum class ConsensusMode {
  intersection,  ///< inside where both traces are
  union_,        ///< inside where either trace is
  average,       ///< mean endpoints (section_traces.h averageTrace)
};
constexpr std::array<NamedChoice<ConsensusMode>, 3> kConsensusModes{{
    {ConsensusMode::intersection, "intersection"},
    {ConsensusMode::union_, "union"},
    {ConsensusMode::average, "average"},
}};

}  // namespace xsect
