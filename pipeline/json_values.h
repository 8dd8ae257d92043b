// Small values as the outputs' JSON writes them (report.json, conformity.json, graph.json, check).
#pragma once

#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "geometry/core/types.h"

namespace xsect {

/// A point or vector as [x, y, z] (mm).
inline nlohmann::ordered_json vecJson(const Vec3& v) { return nlohmann::ordered_json::array({v.x(), v.y(), v.z()}); }

/// A number as JSON writes it (shortest round trip), for text outside JSON.
inline std::string jsonNumber(double v) { return nlohmann::json(v).dump(); }

/// A number with `decimals` digits after the point ("0.550"), for the plain lines `check` and
/// `eval` print.
inline std::string fixedText(double v, int decimals) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(decimals);
  s << v;
  return s.str();
}

}  // namespace xsect
