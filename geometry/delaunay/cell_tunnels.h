// `reconstruction.cell_tunnels` (method 3): whether a tunnel of one cell's R'' that its sections
// do not carry is cut (cell_cycles.h; the thesis' guarantees within a cell assume none, ch. 1 §4.4)
// or kept as the thesis' pruning leaves it.
#pragma once

#include "geometry/core/named_choice.h"

namespace xsect {

enum class CellTunnels {
  cut,  ///< cut (cell_cycles.h), the default
  keep  ///< the thesis' D3 as it is
};
constexpr std::array<NamedChoice<CellTunnels>, 2> kCellTunnels{{
    {CellTunnels::cut, "cut"},
    {CellTunnels::keep, "keep"},
}};

}  // namespace xsect
