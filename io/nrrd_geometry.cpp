// NRRD grid header lines (see nrrd_geometry.h).
#include "io/nrrd_geometry.h"

#include <charconv>

namespace xsect {

std::string nrrdNumber(double v) {
  if (v == 0.0) return "0";  // also -0
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

namespace {
std::string vec3(double x, double y, double z) {
  return "(" + nrrdNumber(x) + "," + nrrdNumber(y) + "," + nrrdNumber(z) + ")";
}
}  // namespace

std::string nrrdGridLines(const GridSpec& grid, const std::string& dataLines) {
  const double v = grid.voxel;
  std::string h = "space: left-posterior-superior\n";
  h += "sizes: " + std::to_string(grid.dims[0]) + " " + std::to_string(grid.dims[1]) + " " +
       std::to_string(grid.dims[2]) + "\n";
  h += "space directions: " + vec3(v, 0, 0) + " " + vec3(0, v, 0) + " " + vec3(0, 0, v) + "\n";
  h += "kinds: domain domain domain\n" + dataLines;
  h += "space origin: " + vec3(grid.origin.x(), grid.origin.y(), grid.origin.z()) + "\n";
  h += "space units: \"mm\" \"mm\" \"mm\"\n";
  return h;
}

}  // namespace xsect
