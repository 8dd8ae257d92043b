// Shortest round-trip decimal text of a double for YAML output (std::to_chars): 0.2 is written
// "0.2", not "0.20000000000000001", and reading the text back gives the same double. Integers are
// written without a decimal point. Locale-independent, so files are byte-identical everywhere.
#pragma once

#include <charconv>
#include <cmath>
#include <string>

namespace xsect {

inline std::string yamlNumberText(double v) {
  if (v == 0.0) return "0";  // also maps -0 to 0
  if (std::isnan(v)) return ".nan";
  if (std::isinf(v)) return v > 0 ? ".inf" : "-.inf";
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace xsect
