// Reproducible gzip streams for volume files (NRRD data). Rows are deflated in parallel, in fixed
// groups of about 1 MiB of input, each group's raw deflate data ended by a sync flush (an empty
// stored block that leaves the stream byte-aligned) and the last one by the final block, as pigz
// does: the groups join into one gzip member that any inflater reads (zlib, Python's gzip and
// pynrrd, ITK/Slicer). The grouping depends on the rows' sizes only, the header carries no file
// name and a modification time of 0, so the same data gives the same bytes whatever the thread count.
#pragma once

#include <cstddef>
#include <functional>
#include <ostream>
#include <string>

namespace xsect {

/// Bytes of row `row` into `bytes` (the callee sizes it). Called from several threads at once,
/// each row once.
using ByteRows = std::function<void(std::size_t row, std::string* bytes)>;

/// Deflates rows 0 .. rows-1 into `out` as one gzip member at zlib `level` (-1: zlib's default,
/// 1: fastest). Throws std::runtime_error on a zlib failure.
void writeGzipRows(std::ostream& out, std::size_t rows, const ByteRows& rowBytes, int level = -1);

}  // namespace xsect
