// PNG / TIFF header reader (see image_header.h). PNG: 8-byte signature, then the IHDR chunk
// (big-endian width, height, bit depth, colour type). TIFF: byte order ("II" or "MM"), 42 (classic:
// 4-byte offsets, 12-byte entries) or 43 (BigTIFF: 8-byte offsets, 20-byte entries), the offset of
// the first image file directory, whose ImageWidth (256), ImageLength (257), BitsPerSample (258) and
// SamplesPerPixel (277) entries give the size.
#include "io/image_header.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <vector>

namespace xsect {
namespace {

/// Reads `count` bytes at `offset`; throws if the file is shorter.
std::vector<unsigned char> bytesAt(std::ifstream& in, std::uint64_t offset, std::size_t count) {
  std::vector<unsigned char> b(count);
  in.clear();
  in.seekg(std::streamoff(offset));
  if (!in || !in.read(reinterpret_cast<char*>(b.data()), std::streamsize(count)))
    throw std::runtime_error("truncated header");
  return b;
}

/// Unsigned integer of `n` bytes at `p` in the file's byte order.
std::uint64_t unsignedAt(const unsigned char* p, int n, bool bigEndian) {
  std::uint64_t v = 0;
  for (int k = 0; k < n; ++k) v |= std::uint64_t(p[bigEndian ? k : n - 1 - k]) << (8 * (n - 1 - k));
  return v;
}

ImageHeader pngHeader(const std::vector<unsigned char>& b) {
  // b: signature (8), IHDR length (4), "IHDR" (4), width (4), height (4), depth (1), colour type (1).
  if (std::string(b.begin() + 12, b.begin() + 16) != "IHDR") throw std::runtime_error("PNG without an IHDR chunk first");
  ImageHeader h;
  h.format = "png";
  h.width = unsignedAt(&b[16], 4, true);
  h.height = unsignedAt(&b[20], 4, true);
  h.bits_per_sample = b[24];
  switch (b[25]) {
    case 0: h.channels = 1; break;
    case 4: h.channels = 2; break;
    case 2: case 3: h.channels = 3; break;
    case 6: h.channels = 4; break;
    default: throw std::runtime_error("PNG with an unknown colour type");
  }
  return h;
}

ImageHeader tiffHeader(std::ifstream& in, const std::vector<unsigned char>& b) {
  const bool big = b[0] == 'M';
  const std::uint64_t version = unsignedAt(&b[2], 2, big);
  if (version != 42 && version != 43) throw std::runtime_error("TIFF of an unknown version");
  const bool bigTiff = version == 43;
  const int offsetBytes = bigTiff ? 8 : 4, countBytes = bigTiff ? 8 : 2, entryBytes = bigTiff ? 20 : 12;
  const std::uint64_t ifd = bigTiff ? unsignedAt(&b[8], 8, big) : unsignedAt(&b[4], 4, big);
  const std::uint64_t entries = unsignedAt(bytesAt(in, ifd, std::size_t(countBytes)).data(), countBytes, big);
  if (entries == 0 || entries > 4096) throw std::runtime_error("TIFF directory with " + std::to_string(entries) + " entries");
  const std::vector<unsigned char> dir = bytesAt(in, ifd + std::uint64_t(countBytes), std::size_t(entries * entryBytes));
  ImageHeader h;
  h.format = "tiff";
  bool palette = false;
  for (std::uint64_t e = 0; e < entries; ++e) {
    const unsigned char* p = &dir[std::size_t(e * entryBytes)];
    const std::uint64_t tag = unsignedAt(p, 2, big), type = unsignedAt(p + 2, 2, big);
    const std::uint64_t count = unsignedAt(p + 4, offsetBytes, big);  // the count field: 4 or 8 bytes
    const unsigned char* value = p + 4 + offsetBytes;  // after tag, type and count
    // Values sit left-justified in the value field: BYTE (1), SHORT (3) and LONG (4), and their
    // signed forms (6, 8, 9: sizes are never negative), and LONG8 (16), which exists only in
    // BigTIFF, whose value field has room for it.
    const std::uint64_t v = type == 1 || type == 6 ? value[0]
                            : type == 3 || type == 8 ? unsignedAt(value, 2, big)
                            : type == 4 || type == 9 ? unsignedAt(value, 4, big)
                            : type == 16 && bigTiff ? unsignedAt(value, 8, big) : 0;
    if (tag == 256) h.width = v;
    if (tag == 257) h.height = v;
    // Bits per sample: the first sample's, inline for one sample (for more, the field holds an
    // offset; the samples are then refused as channels anyway).
    if (tag == 258 && type == 3 && count == 1) h.bits_per_sample = int(v);
    if (tag == 262 && v == 3) palette = true;  // PhotometricInterpretation: palette colour
    if (tag == 277) h.channels = int(std::min<std::uint64_t>(v, 1u << 16));
  }
  if (palette) h.channels = 3;  // decoded as colour
  return h;
}

}  // namespace

ImageHeader readImageHeader(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open the file");
  std::vector<unsigned char> b(26, 0);
  in.read(reinterpret_cast<char*>(b.data()), std::streamsize(b.size()));
  const std::size_t got = std::size_t(in.gcount());
  static constexpr unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  ImageHeader h;
  if (got >= 8 && std::equal(kPng, kPng + 8, b.begin())) {
    if (got < 26) throw std::runtime_error("truncated header");
    h = pngHeader(b);
  } else if (got >= 8 && ((b[0] == 'I' && b[1] == 'I') || (b[0] == 'M' && b[1] == 'M'))) {
    if (got < 16 && b[2 + (b[0] == 'M')] == 43) throw std::runtime_error("truncated header");
    h = tiffHeader(in, b);
  } else {
    throw std::runtime_error("neither a PNG nor a TIFF image");
  }
  if (h.width == 0 || h.height == 0) throw std::runtime_error("the header gives no size");
  if (h.width > 0xffffffffu || h.height > 0xffffffffu) throw std::runtime_error("the header gives a size past 2^32 pixels");
  return h;
}

}  // namespace xsect
