// One gzip member from row groups deflated in parallel (see gzip_stream.h).
#include "io/gzip_stream.h"

#include <tbb/parallel_for.h>
#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace xsect {

namespace {

/// Raw deflate of `in`, ended by a sync flush, or by the final block when `last`.
std::string deflateGroup(const std::string& in, int level, bool last) {
  z_stream zs;
  std::memset(&zs, 0, sizeof zs);
  // windowBits -15: raw deflate data, no wrapper (the member's header and trailer are written once).
  if (deflateInit2(&zs, level, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::runtime_error("zlib: deflateInit2 failed");
  struct Guard { z_stream* z; ~Guard() { deflateEnd(z); } } guard{&zs};
  std::string out(deflateBound(&zs, uLong(in.size())) + 16, '\0');
  zs.next_in = reinterpret_cast<unsigned char*>(const_cast<char*>(in.data()));
  zs.avail_in = uInt(in.size());
  std::size_t used = 0;
  for (;;) {  // one call suffices with deflateBound's room; more room if zlib ever asks for it
    zs.next_out = reinterpret_cast<unsigned char*>(out.data() + used);
    zs.avail_out = uInt(out.size() - used);
    const int rc = deflate(&zs, last ? Z_FINISH : Z_SYNC_FLUSH);
    if (rc == Z_STREAM_ERROR) throw std::runtime_error("zlib: deflate failed");
    used = out.size() - zs.avail_out;
    const bool done = last ? rc == Z_STREAM_END : (zs.avail_in == 0 && zs.avail_out > 0);
    if (done) break;
    if (rc != Z_OK && rc != Z_BUF_ERROR) throw std::runtime_error("zlib: deflate failed");
    out.resize(out.size() * 2);
  }
  out.resize(used);
  return out;
}

}  // namespace

void writeGzipRows(std::ostream& out, std::size_t rows, const ByteRows& rowBytes, int level) {
  // The groups: rows of about 1 MiB of input together (sizes from the first row; volume rows are
  // all alike), processed a wave at a time so that memory stays a few groups per thread.
  std::string first;
  if (rows > 0) rowBytes(0, &first);
  const std::size_t perGroup = std::max<std::size_t>(1, (std::size_t(1) << 20) / std::max<std::size_t>(1, first.size()));
  const std::size_t groups = std::max<std::size_t>(1, (rows + perGroup - 1) / perGroup);
  constexpr std::size_t kWave = 16;

  // gzip header (RFC 1952): no name, mtime 0, XFL as zlib sets it (2: best compression, 4: the
  // fastest levels 0 and 1), OS 3 (Unix) on every host.
  const unsigned char xfl = level == 9 ? 2 : (level == 0 || level == 1) ? 4 : 0;
  const unsigned char header[10] = {0x1f, 0x8b, 8, 0, 0, 0, 0, 0, xfl, 3};
  out.write(reinterpret_cast<const char*>(header), sizeof header);
  uLong crc = crc32(0L, Z_NULL, 0);
  std::uint64_t length = 0;
  std::vector<std::string> deflated(kWave);
  std::vector<uLong> crcs(kWave);
  std::vector<std::size_t> sizes(kWave);
  for (std::size_t w0 = 0; w0 < groups; w0 += kWave) {
    const std::size_t n = std::min(kWave, groups - w0);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t g) {
      const std::size_t r0 = (w0 + g) * perGroup, r1 = std::min(rows, r0 + perGroup);
      std::string in, row;
      for (std::size_t r = r0; r < r1; ++r) {
        if (r == 0) in += first;
        else {
          rowBytes(r, &row);
          in += row;
        }
      }
      crcs[g] = crc32(0L, reinterpret_cast<const Bytef*>(in.data()), uInt(in.size()));
      sizes[g] = in.size();
      deflated[g] = deflateGroup(in, level, w0 + g + 1 == groups);
    });
    for (std::size_t g = 0; g < n; ++g) {
      out.write(deflated[g].data(), std::streamsize(deflated[g].size()));
      crc = crc32_combine(crc, crcs[g], z_off_t(sizes[g]));
      length += sizes[g];
    }
  }
  // Trailer: CRC-32 and the input's length modulo 2^32, little-endian.
  unsigned char trailer[8];
  for (int b = 0; b < 4; ++b) {
    trailer[b] = static_cast<unsigned char>((crc >> (8 * b)) & 0xff);
    trailer[4 + b] = static_cast<unsigned char>((length >> (8 * b)) & 0xff);
  }
  out.write(reinterpret_cast<const char*>(trailer), sizeof trailer);
}

}  // namespace xsect
