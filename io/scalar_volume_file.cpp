// Float NRRD volumes (see scalar_volume_file.h).
#include "io/scalar_volume_file.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <zlib.h>

#include "io/gzip_stream.h"
#include "io/nrrd_geometry.h"

namespace xsect {

void writeScalarVolumeNrrd(const std::string& path, const GridSpec& grid, const ScalarRows& rows,
                           const std::string& description) {
  for (int c = 0; c < 3; ++c)
    if (grid.dims[c] < 1) throw std::invalid_argument("writeScalarVolumeNrrd: grid dims must be positive");
  if (!(grid.voxel > 0.0) || !std::isfinite(grid.voxel) || !grid.origin.allFinite())
    throw std::invalid_argument("writeScalarVolumeNrrd: invalid grid geometry");
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot write " + path);
  std::string h = "NRRD0004\n# " + description + "\ntype: float\ndimension: 3\n";
  h += nrrdGridLines(grid, "endian: little\nencoding: gzip\n");
  h += "\n";
  out.write(h.data(), std::streamsize(h.size()));
  const int nx = grid.dims[0], ny = grid.dims[1];
  writeGzipRows(out, std::size_t(ny) * std::size_t(grid.dims[2]), [&](std::size_t r, std::string* bytes) {
    std::vector<float> row(static_cast<std::size_t>(nx));  // rows come from several threads
    rows(int(r % std::size_t(ny)), int(r / std::size_t(ny)), row.data());
    bytes->resize(4 * std::size_t(nx));
    for (int i = 0; i < nx; ++i) {  // little-endian whatever the host
      std::uint32_t u;
      std::memcpy(&u, &row[std::size_t(i)], 4);
      for (int b = 0; b < 4; ++b) (*bytes)[4 * std::size_t(i) + std::size_t(b)] = char((u >> (8 * b)) & 0xff);
    }
  }, Z_BEST_SPEED);  // diagnostics of the whole grid: speed over size (runs of equal values pack well anyway)
  out.flush();
  if (!out) throw std::runtime_error("error while writing " + path);
}

}  // namespace xsect
