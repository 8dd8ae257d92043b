// Reproducible gzip streams for volume files (NRRD data): the rows of a volume go in as they come
// (deflate's output does not depend on how its input is cut up) and zlib writes no file name and a
// modification time of 0, so writing the same data twice gives the same bytes.
#pragma once

#include <cstddef>
#include <functional>
#include <ostream>
#include <string>

namespace xsect {

/// Bytes of row `row` into `bytes` (the callee sizes it).
using ByteRows = std::function<void(std::size_t row, std::string* bytes)>;

/// Deflates rows 0 .. rows-1 into `out` as one gzip member at zlib `level` (-1: zlib's default,
/// 1: fastest). Throws std::runtime_error on a zlib failure.
void writeGzipRows(std::ostream& out, std::size_t rows, const ByteRows& rowBytes, int level = -1);

}  // namespace xsect
