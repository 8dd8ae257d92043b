// gzip member written row by row (see gzip_stream.h).
#include "io/gzip_stream.h"

#include <zlib.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace xsect {

void writeGzipRows(std::ostream& out, std::size_t rows, const ByteRows& rowBytes, int level) {
  z_stream zs;
  std::memset(&zs, 0, sizeof zs);
  // windowBits 15 + 16: a gzip wrapper with no name and mtime 0.
  if (deflateInit2(&zs, level, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::runtime_error("zlib: deflateInit2 failed");
  struct Guard { z_stream* z; ~Guard() { deflateEnd(z); } } guard{&zs};
  std::string in;
  std::vector<unsigned char> buf(1 << 17);
  for (std::size_t r = 0; r < rows || r == 0; ++r) {
    in.clear();
    if (r < rows) rowBytes(r, &in);
    const int flush = r + 1 >= rows ? Z_FINISH : Z_NO_FLUSH;
    zs.next_in = reinterpret_cast<unsigned char*>(in.data());
    zs.avail_in = uInt(in.size());
    int rc;
    do {
      zs.next_out = buf.data();
      zs.avail_out = uInt(buf.size());
      rc = deflate(&zs, flush);
      if (rc == Z_STREAM_ERROR) throw std::runtime_error("zlib: deflate failed");
      out.write(reinterpret_cast<const char*>(buf.data()), std::streamsize(buf.size() - zs.avail_out));
    } while (zs.avail_out == 0 || (flush == Z_FINISH && rc != Z_STREAM_END));
  }
}

}  // namespace xsect
