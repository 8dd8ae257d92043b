// What the user asks of the solid's topology (issue 51, `reconstruction.topology`): free (the
// method's own solid), simplest (the fewest components, tunnels and cavities the sections allow),
// or target Betti numbers [b0, b1, b2]. Read from the configuration (io/run_config.h), met by
// controlTopology (topology_control.h).
#pragma once

#include <array>

#include "geometry/core/named_choice.h"

namespace xsect {

enum class TopologyMode { free, simplest, target };

/// The names `reconstruction.topology` takes besides a target [b0, b1, b2].
inline constexpr std::array<NamedChoice<TopologyMode>, 2> kTopologyModes{{{TopologyMode::free, "free"},
                                                                          {TopologyMode::simplest, "simplest"}}};

struct TopologyGoal {
  TopologyMode mode = TopologyMode::free;
  std::array<int, 3> target{1, 0, 0};  ///< mode target: b0 (>= 1), b1, b2
  double min_feature_mm = 0;           ///< mode simplest: joins wider than this are kept, no mend wider is made (0: no limit)
  int max_evaluations = 400;           ///< changes evaluated at most (each one Betti computation of the solid's box)
};

}  // namespace xsect
