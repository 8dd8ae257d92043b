// Base64 (RFC 4648, with padding): binary data inlined in report.html (typed arrays, PNG images).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace xsect {

/// The `size` bytes at `data` in base64.
inline std::string base64(const void* data, std::size_t size) {
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const std::uint8_t*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < size; i += 3) {
    const std::uint32_t w = (std::uint32_t(p[i]) << 16) | (std::uint32_t(p[i + 1]) << 8) | p[i + 2];
    out += kDigits[w >> 18];
    out += kDigits[(w >> 12) & 63];
    out += kDigits[(w >> 6) & 63];
    out += kDigits[w & 63];
  }
  if (i < size) {
    const std::uint32_t w = (std::uint32_t(p[i]) << 16) | (i + 1 < size ? std::uint32_t(p[i + 1]) << 8 : 0);
    out += kDigits[w >> 18];
    out += kDigits[(w >> 12) & 63];
    out += i + 1 < size ? kDigits[(w >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

}  // namespace xsect
