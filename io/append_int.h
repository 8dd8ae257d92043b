// Decimal text of an integer appended to a string in place (std::to_chars): the writers of large
// text files (graph.json's edge lists, graph.dot) build them without a temporary per number.
#pragma once

#include <charconv>
#include <string>

namespace xsect {

inline void appendInt(std::string& out, long long v) {
  char buf[24];
  out.append(buf, std::size_t(std::to_chars(buf, buf + sizeof buf, v).ptr - buf));
}

}  // namespace xsect
