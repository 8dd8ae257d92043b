// SHA-256 of files and strings (OpenSSL), hex encoded, for the run manifest.
#pragma once

#include <string>

namespace xsect {

std::string sha256Hex(const std::string& bytes);
/// Throws std::runtime_error if the file cannot be read.
std::string sha256File(const std::string& path);

}  // namespace xsect
