// Base64 (RFC 4648, with padding, no line breaks): binary data inlined in report.html (typed
// arrays, PNG images), encoded by OpenSSL (EVP_EncodeBlock).
#pragma once

#include <cstddef>
#include <string>

namespace xsect {

/// The `size` bytes at `data` in base64.
std::string base64(const void* data, std::size_t size);

}  // namespace xsect
