// Duplicated keys in a YAML mapping (issue 48): yaml-cpp keeps the first and drops the others
// silently, so two `reconstruction:` blocks ran with the first one's settings and exit 0. The
// document's events are read once more (yaml-cpp's event parser) and the second key of any
// mapping that names a key twice is an input error naming both lines.
#pragma once

#include <string>

namespace xsect {

/// Throws InputError(file, "key.path", "given twice (lines A and B) ...", B) at the first
/// duplicated key of any mapping in `text`, at any depth (lists indexed: "slices[3].image").
/// Syntax errors are left to the loader (nothing is thrown for them here).
void checkNoDuplicateKeys(const std::string& text, const std::string& file);

}  // namespace xsect
