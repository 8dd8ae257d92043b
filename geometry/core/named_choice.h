// Choices that configurations name (a method, a mode): each enum has one table of its names, from
// which the YAML reader parses it once, where the file is read, and the writers name it again.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>

namespace xsect {

template <typename E>
struct NamedChoice {
  E value;
  const char* name;
};

/// The value called `name` in `table`, or nothing.
template <typename E, std::size_t N>
std::optional<E> choiceNamed(const std::array<NamedChoice<E>, N>& table, const std::string& name) {
  for (const NamedChoice<E>& c : table)
    if (name == c.name) return c.value;
  return std::nullopt;
}

/// The name of `value` in `table` ("?" if the table lacks it, which a test of each table rules out).
template <typename E, std::size_t N>
const char* nameOf(const std::array<NamedChoice<E>, N>& table, E value) {
  for (const NamedChoice<E>& c : table)
    if (c.value == value) return c.name;
  return "?";
}

/// "a | b | c": the names, for messages.
template <typename E, std::size_t N>
std::string choiceNames(const std::array<NamedChoice<E>, N>& table) {
  std::string s;
  for (const NamedChoice<E>& c : table) s += (s.empty() ? "" : " | ") + std::string(c.name);
  return s;
}

}  // namespace xsect
