// The largest coordinate an input may give (issue 48): a vertex of 1e308 in a .csl or a
// translation of 1e300 in a pose is a corrupt export, not a scan, and let through it surfaced as
// "no section found" or as a voxel size too small for a grid spanning 1e300. A kilometre in
// nanometres is 1e12: no acquisition in any unit of length comes near it.
#pragma once

#include <sstream>
#include <string>

namespace xsect {

inline constexpr double kMaxCoordinate = 1e12;

/// "a coordinate of V is beyond any acquisition (|x| <= 1e12 in the file's units): ..."
inline std::string coordinateRangeMessage(double v) {
  std::ostringstream s;
  s << "a coordinate of " << v << " is beyond any acquisition (|x| <= 1e12 in the file's units): "
    << "the file is corrupt or was exported in the wrong units";
  return s.str();
}

}  // namespace xsect
