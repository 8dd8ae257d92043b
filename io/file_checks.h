// Checks on input paths. isRegularFile: whether a path names a readable regular file, without
// throwing: std::filesystem's checks throw on paths the system refuses (a name over NAME_MAX,
// found by the slices.yaml fuzzer), and a path from an input file is input, to be refused with
// InputError naming its field. lowerExtension: the extension that decides a file's format.
#pragma once

#include <cctype>
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

/// The extension of the path's last component, lower case, without the dot ("" without one).
inline std::string lowerExtension(const std::string& path) {
  const auto slash = path.find_last_of("/\\");
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace xsect
