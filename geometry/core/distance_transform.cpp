// Exact squared Euclidean distance transform, separable (see distance_transform.h).
#include "geometry/core/distance_transform.h"

#include <stdexcept>

namespace xsect {

namespace {

/// One line of samples f (squared distances so far) replaced by min_q ((p - q)² + f(q)): the lower
/// envelope of the parabolas rooted at the finite samples.
void envelope(std::vector<float>& f, std::vector<int>& root, std::vector<double>& bound, std::vector<float>& out) {
  const int n = int(f.size());
  int roots = 0;
  for (int q = 0; q < n; ++q) {
    if (f[std::size_t(q)] >= kNoVoxel) continue;
    const double fq = double(f[std::size_t(q)]) + double(q) * q;
    double s = -1e300;
    while (roots > 0) {
      const int r = root[std::size_t(roots - 1)];
      s = (fq - (double(f[std::size_t(r)]) + double(r) * r)) / (2.0 * (q - r));
      if (s > bound[std::size_t(roots - 1)]) break;
      --roots;
    }
    root[std::size_t(roots)] = q;
    bound[std::size_t(roots)] = roots == 0 ? -1e300 : s;
    ++roots;
  }
  if (roots == 0) return;  // no sample on the line: it stays kNoVoxel
  int at = 0;
  for (int p = 0; p < n; ++p) {
    while (at + 1 < roots && bound[std::size_t(at + 1)] < p) ++at;
    const int r = root[std::size_t(at)];
    out[std::size_t(p)] = float(double(p - r) * (p - r) + f[std::size_t(r)]);
  }
  f.swap(out);
}

}  // namespace

std::vector<float> squaredDistanceToSet(const std::vector<std::uint8_t>& set, const GridSpec& grid) {
  if (set.size() != std::size_t(grid.count()))
    throw std::invalid_argument("squaredDistanceToSet: the set does not hold one value per voxel of the grid");
  std::vector<float> d(set.size());
  for (std::size_t v = 0; v < set.size(); ++v) d[v] = set[v] ? 0.0f : kNoVoxel;
  const std::array<std::int64_t, 3> stride{1, grid.dims[0], std::int64_t(grid.dims[0]) * grid.dims[1]};
  for (int axis = 0; axis < 3; ++axis) {
    const int n = grid.dims[std::size_t(axis)];
    const int u = axis == 0 ? 1 : 0, w = axis == 2 ? 1 : 2;  // the two other axes
    std::vector<float> line(static_cast<std::size_t>(n)), out(static_cast<std::size_t>(n));
    std::vector<int> root(static_cast<std::size_t>(n));
    std::vector<double> bound(static_cast<std::size_t>(n));
    for (int b = 0; b < grid.dims[std::size_t(w)]; ++b)
      for (int a = 0; a < grid.dims[std::size_t(u)]; ++a) {
        const std::int64_t base = a * stride[std::size_t(u)] + b * stride[std::size_t(w)];
        for (int p = 0; p < n; ++p) line[std::size_t(p)] = d[std::size_t(base + p * stride[std::size_t(axis)])];
        std::fill(out.begin(), out.end(), kNoVoxel);
        envelope(line, root, bound, out);
        for (int p = 0; p < n; ++p) d[std::size_t(base + p * stride[std::size_t(axis)])] = line[std::size_t(p)];
      }
  }
  return d;
}

}  // namespace xsect
