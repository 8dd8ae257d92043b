// Exact squared Euclidean distance transform, separable (see distance_transform.h).
#include "geometry/core/distance_transform.h"

#include <algorithm>
#include <array>
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

std::vector<float> squaredDistanceToSet(const std::vector<std::uint8_t>& set, const GridSpec& grid, double reach) {
  if (set.size() != std::size_t(grid.count()))
    throw std::invalid_argument("squaredDistanceToSet: the set does not hold one value per voxel of the grid");
  std::vector<float> d(set.size());
  const std::array<std::int64_t, 3> stride{1, grid.dims[0], std::int64_t(grid.dims[0]) * grid.dims[1]};
  // The first pass, along x, of a binary line: the distance to the nearest voxel of the set on the
  // line, two sweeps; past the reach (or with none on the line) kNoVoxel.
  const double cap = std::min(reach, 1e9);
  const int nx = grid.dims[0];
  for (std::int64_t row = 0; row < std::int64_t(grid.dims[1]) * grid.dims[2]; ++row) {
    const std::size_t base = std::size_t(row * nx);
    int last = -1;
    for (int i = 0; i < nx; ++i) {
      if (set[base + std::size_t(i)]) last = i;
      d[base + std::size_t(i)] = last < 0 || i - last > cap ? kNoVoxel : float(double(i - last) * (i - last));
    }
    last = -1;
    for (int i = nx - 1; i >= 0; --i) {
      if (set[base + std::size_t(i)]) last = i;
      if (last >= 0 && last - i <= cap) d[base + std::size_t(i)] = std::min(d[base + std::size_t(i)], float(double(last - i) * (last - i)));
    }
  }
  const double reach2 = cap * cap;
  for (int axis = 1; axis < 3; ++axis) {
    const int n = grid.dims[std::size_t(axis)];
    const int u = axis == 0 ? 1 : 0, w = axis == 2 ? 1 : 2;  // the two other axes
    std::vector<float> line(static_cast<std::size_t>(n)), out(static_cast<std::size_t>(n));
    std::vector<int> root(static_cast<std::size_t>(n));
    std::vector<double> bound(static_cast<std::size_t>(n));
    for (int b = 0; b < grid.dims[std::size_t(w)]; ++b)
      for (int a = 0; a < grid.dims[std::size_t(u)]; ++a) {
        const std::int64_t base = a * stride[std::size_t(u)] + b * stride[std::size_t(w)];
        bool any = false;  // a sample within the reach: else the line stays as it is
        for (int p = 0; p < n; ++p) {
          float& v = line[std::size_t(p)];
          v = d[std::size_t(base + p * stride[std::size_t(axis)])];
          if (double(v) > reach2) v = kNoVoxel;
          any = any || v < kNoVoxel;
        }
        if (!any) continue;
        std::fill(out.begin(), out.end(), kNoVoxel);
        envelope(line, root, bound, out);
        for (int p = 0; p < n; ++p) d[std::size_t(base + p * stride[std::size_t(axis)])] = line[std::size_t(p)];
      }
  }
  return d;
}

}  // namespace xsect
