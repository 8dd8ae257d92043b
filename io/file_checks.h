// Whether a path names a readable regular file, without throwing: std::filesystem's checks throw
// on paths the system refuses (a name over NAME_MAX, found by the slices.yaml fuzzer), and a path
// from an input file is input, to be refused with InputError naming its field.
#pragma once

#include <filesystem>
#include <string>
#include <system_error>

namespace xsect {

/// True when `path` is a regular file (following links); false when it is not, or cannot be
/// examined (missing, a name too long, no permission).
inline bool isRegularFile(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec) && !ec;
}

}  // namespace xsect
