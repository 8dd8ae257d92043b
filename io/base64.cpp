// Base64 by OpenSSL (see base64.h).
#include "io/base64.h"

#include <openssl/evp.h>

#include <algorithm>

namespace xsect {

std::string base64(const void* data, std::size_t size) {
  const auto* p = static_cast<const unsigned char*>(data);
  std::string out((size + 2) / 3 * 4, '\0');
  // EVP_EncodeBlock takes an int length: whole groups of 3 bytes at a time, so that the pieces join
  // into one encoding (padding only at the end). Each call ends its output with a NUL: the next
  // piece's first character, or the string's own terminator.
  constexpr std::size_t kChunk = std::size_t(3) << 28;
  auto* o = reinterpret_cast<unsigned char*>(out.data());
  for (std::size_t at = 0; at < size; at += kChunk) {
    const std::size_t n = std::min(kChunk, size - at);
    o += EVP_EncodeBlock(o, p + at, int(n));
  }
  return out;
}

}  // namespace xsect
