// Writing a text file: checked (the open and the write), or atomically (a temporary sibling renamed
// into place, so that the file is either the old one or complete: for outputs written outside a
// StagedOutput folder).
#pragma once

#include <string>

namespace xsect {

/// Writes `text` to `path` (bytes as given). Throws std::runtime_error naming the file when it
/// cannot be opened or written.
void writeTextFile(const std::string& path, const std::string& text);

/// As writeTextFile, through a temporary sibling renamed onto `path`; creates the folder. On
/// failure the temporary is removed and `path` is left as it was.
void writeTextFileAtomically(const std::string& path, const std::string& text);

}  // namespace xsect
