// Plain-text number files (.csl, .contour) as whitespace-separated tokens with their line numbers,
// read in order: numbers (finite), integers (with a lower bound) and counts (checked against what
// the file still holds, before anything is allocated for them). Every error is an InputError
// naming the file, the field and the line.
#pragma once

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "io/coordinate_limit.h"
#include "io/input_error.h"

namespace xsect {

/// Whitespace tokens with their line numbers, consumed from the front.
struct Tokens {
  std::vector<std::pair<std::string, int>> items;  ///< (token, 1-based line)
  std::size_t at = 0;                              ///< index of the next token
  std::string file;                                ///< the file's path, for messages

  /// The next token; `what` names the field for the message at the end of the file.
  const std::pair<std::string, int>& next(const std::string& what) {
    if (at >= items.size())
      throw InputError(file, what, "unexpected end of file",
                       items.empty() ? -1 : items.back().second);
    return items[at++];
  }
  /// The next token as a finite number (the file's unit); `what` names the field.
  double number(const std::string& what) {
    const auto& [t, line] = next(what);
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (end == t.c_str() || *end != '\0' || !std::isfinite(v))
      throw InputError(file, what, "expected a number, got '" + t + "'", line);
    return v;
  }
  /// The next token as a coordinate: a number of magnitude at most kMaxCoordinate.
  double coordinate(const std::string& what) {
    const double v = number(what);
    if (std::abs(v) > kMaxCoordinate)
      throw InputError(file, what, coordinateRangeMessage(v), items[at - 1].second);
    return v;
  }
  /// The next token as an integer >= `lo` (dimensionless); `what` names the field.
  long integer(const std::string& what, long lo) {
    const auto& [t, line] = next(what);
    char* end = nullptr;
    const long v = std::strtol(t.c_str(), &end, 10);
    if (end == t.c_str() || *end != '\0' || v < lo)
      throw InputError(file, what, "expected an integer >= " + std::to_string(lo) + ", got '" + t + "'", line);
    return v;
  }
  /// A count >= `lo` checked against what the file can still hold (`tokens_each` tokens per
  /// item), before anything is allocated for it: a corrupt count is an input error, not an
  /// allocation failure. `what` names the field.
  long count(const std::string& what, long lo, long tokens_each) {
    const long v = integer(what, lo);
    const long left = long(items.size() - at);
    if (v > left / tokens_each)
      throw InputError(file, what,
                       std::to_string(v) + " items need at least " + std::to_string(tokens_each) +
                           " values each, but the file holds only " + std::to_string(left) + " more",
                       items[at - 1].second);
    return v;
  }
  /// Line of the next token (of the last one at the end of the file; -1 when there is none).
  int line() const {
    if (items.empty()) return -1;
    return items[at < items.size() ? at : items.size() - 1].second;
  }
};

/// Every whitespace-separated token of the text file at `path`, with its line. Throws
/// InputError(path, "", "cannot open file") when it cannot be opened.
inline Tokens readTokens(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "", "cannot open file");
  Tokens tk;
  tk.file = path;
  std::string line;
  for (int ln = 1; std::getline(in, line); ++ln) {
    std::istringstream ss(line);
    for (std::string t; ss >> t;) tk.items.emplace_back(t, ln);
  }
  return tk;
}

}  // namespace xsect
