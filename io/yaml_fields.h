// Typed, validated access to YAML fields: every failure is an InputError naming the file, the key
// path (e.g. "slices[3].image_to_world[1][2]") and the line.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <string>

#include "geometry/core/named_choice.h"
#include "io/input_error.h"

namespace xsect {

/// 1-based line of a node, -1 when unknown (a missing node has no position: Mark() would throw).
inline int yamlLine(const YAML::Node& n) {
  if (!n.IsDefined()) return -1;
  return n.Mark().line >= 0 ? n.Mark().line + 1 : -1;
}

inline YAML::Node loadYamlFile(const std::string& path) {
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw InputError(path, "", "cannot open file");
  } catch (const YAML::ParserException& e) {
    throw InputError(path, "", "not valid YAML: " + e.msg, e.mark.line + 1);
  }
}

inline double yamlNumber(const YAML::Node& n, const std::string& file, const std::string& key) {
  if (!n || !n.IsScalar()) throw InputError(file, key, "expected a number", yamlLine(n));
  double v;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(file, key, "expected a number, got '" + n.Scalar() + "'", yamlLine(n));
  }
  if (!std::isfinite(v)) throw InputError(file, key, "number is not finite", yamlLine(n));
  return v;
}

/// An integer in [lo, hi] (a YAML number without fractional part).
inline int yamlInteger(const YAML::Node& n, const std::string& file, const std::string& key, int lo, int hi) {
  const double v = yamlNumber(n, file, key);
  if (v != std::floor(v) || v < lo || v > hi)
    throw InputError(file, key,
                     "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] (got " +
                         n.Scalar() + ")",
                     yamlLine(n));
  return int(v);
}

inline std::string yamlString(const YAML::Node& n, const std::string& file,
                              const std::string& key) {
  if (!n || !n.IsScalar()) throw InputError(file, key, "expected a string", yamlLine(n));
  return n.Scalar();
}

/// The choice `n` names in `table`; InputError "unknown <noun> 'x' (a | b | c)" otherwise.
template <typename E, std::size_t N>
E yamlChoice(const YAML::Node& n, const std::string& file, const std::string& key,
             const std::array<NamedChoice<E>, N>& table, const std::string& noun) {
  const std::string name = yamlString(n, file, key);
  if (const std::optional<E> v = choiceNamed(table, name)) return *v;
  throw InputError(file, key, "unknown " + noun + " '" + name + "' (" + choiceNames(table) + ")", yamlLine(n));
}

inline bool yamlBool(const YAML::Node& n, const std::string& file, const std::string& key) {
  if (!n || !n.IsScalar()) throw InputError(file, key, "expected true or false", yamlLine(n));
  try {
    return n.as<bool>();
  } catch (const YAML::Exception&) {
    throw InputError(file, key, "expected true or false, got '" + n.Scalar() + "'", yamlLine(n));
  }
}

}  // namespace xsect
