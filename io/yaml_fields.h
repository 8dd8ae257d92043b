// Typed, validated access to YAML fields: every failure is an InputError naming the file, the key
// path (e.g. "slices[3].image_to_world[1][2]") and the line. A key given twice in a mapping is
// an error too (io/yaml_duplicate_keys.h).
#pragma once

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/core/named_choice.h"
#include "io/closest_name.h"
#include "io/input_error.h"
#include "io/yaml_duplicate_keys.h"

namespace xsect {

/// 1-based line of a node, -1 when unknown (a missing node has no position: Mark() would throw).
inline int yamlLine(const YAML::Node& n) {
  if (!n.IsDefined()) return -1;
  return n.Mark().line >= 0 ? n.Mark().line + 1 : -1;
}

/// A YAML document given as text (a file's contents, a --set value, a block of a phantom spec),
/// parsed; `file` names it in errors. Syntax errors and duplicated keys are InputErrors.
inline YAML::Node loadYamlText(const std::string& text, const std::string& file) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(file, "", "not valid YAML: " + e.msg, e.mark.line + 1);
  }
  checkNoDuplicateKeys(text, file);
  return root;
}

inline YAML::Node loadYamlFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(path, "", "cannot read file");
  return loadYamlText(text.str(), path);
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
  std::vector<std::string> names;
  for (const NamedChoice<E>& c : table) names.push_back(c.name);
  throw InputError(file, key,
                   "unknown " + noun + " '" + name + "'" + didYouMean(name, names) + " (" + choiceNames(table) + ")",
                   yamlLine(n));
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
