// Base64 of report.html's inlined data (io/base64.h): RFC 4648's test vectors, and every byte value
// decoding back.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "io/base64.h"

using namespace xsect;

TEST(Base64, Rfc4648TestVectors) {
  const std::pair<std::string, std::string> vectors[] = {{"", ""},         {"f", "Zg=="},         {"fo", "Zm8="},
                                                         {"foo", "Zm9v"}, {"foob", "Zm9vYg=="}, {"fooba", "Zm9vYmE="},
                                                         {"foobar", "Zm9vYmFy"}};
  for (const auto& [in, want] : vectors) EXPECT_EQ(base64(in.data(), in.size()), want) << in;
}

TEST(Base64, EveryByteValueDecodesBack) {
  std::vector<unsigned char> bytes(256 * 3 + 1);
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<unsigned char>(i * 7 + i / 256);
  const std::string text = base64(bytes.data(), bytes.size());
  ASSERT_EQ(text.size(), (bytes.size() + 2) / 3 * 4);
  const std::string digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<unsigned char> back;
  for (std::size_t i = 0; i < text.size(); i += 4) {
    unsigned v = 0;
    int pad = 0;
    for (int k = 0; k < 4; ++k) {
      const char c = text[i + std::size_t(k)];
      pad += c == '=';
      v = v << 6 | (c == '=' ? 0u : unsigned(digits.find(c)));
    }
    for (int k = 0; k < 3 - pad; ++k) back.push_back(static_cast<unsigned char>(v >> (16 - 8 * k)));
  }
  EXPECT_EQ(back, bytes);
}
