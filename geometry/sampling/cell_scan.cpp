// Lattice scan of the arrangement's cells (see cell_scan.h).
#include "geometry/sampling/cell_scan.h"

#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "geometry/core/random_streams.h"

namespace xsect {

CellKeys::CellKeys(const std::vector<Plane>& planes) {
  for (std::size_t j = 0; j < planes.size(); ++j) {
    nx_.push_back(planes[j].normal.x());
    ny_.push_back(planes[j].normal.y());
    nz_.push_back(planes[j].normal.z());
    offsets_.push_back(planes[j].normal.dot(planes[j].origin));
    keys_.push_back(splitMix64(0x5EC7C011ULL ^ (std::uint64_t(j) * 0x9E3779B97F4A7C15ULL)));
  }
}

namespace {

/// XOR of the keys of planes [from, to) with x on their positive side, and the least |distance|.
inline void accumulate(const double* nx, const double* ny, const double* nz, const double* off,
                       const std::uint64_t* keys, std::size_t from, std::size_t to, double px, double py, double pz,
                       std::uint64_t* key, double* clearance) {
  std::uint64_t k = *key;
  double c = *clearance;
  for (std::size_t j = from; j < to; ++j) {
    const double d = nx[j] * px + ny[j] * py + nz[j] * pz - off[j];
    k ^= keys[j] & (std::uint64_t(0) - std::uint64_t(d > 0));
    c = std::min(c, std::abs(d));
  }
  *key = k;
  *clearance = c;
}

}  // namespace

std::uint64_t CellKeys::of(const Vec3& x, int onPlane, int side, double* clearance, int onPlane2, int side2) const {
  std::uint64_t k = 0;
  double c = std::numeric_limits<double>::infinity();
  const std::size_t n = keys_.size();
  // The planes x lies on, in order: their sides as asked, and not counted in the clearance.
  std::array<std::pair<std::size_t, int>, 2> forced{{{onPlane >= 0 ? std::size_t(onPlane) : n, side},
                                                    {onPlane2 >= 0 ? std::size_t(onPlane2) : n, side2}}};
  if (forced[1].first < forced[0].first) std::swap(forced[0], forced[1]);
  std::size_t from = 0;
  for (const auto& [plane, s] : forced) {
    const std::size_t to = std::min(plane, n);
    if (from < to)
      accumulate(nx_.data(), ny_.data(), nz_.data(), offsets_.data(), keys_.data(), from, to, x.x(), x.y(), x.z(),
                 &k, &c);
    from = std::max(from, to);
    if (plane >= n) break;
    if (s > 0 && plane >= from) k ^= keys_[plane];
    from = std::max(from, plane + 1);
  }
  if (from < n)
    accumulate(nx_.data(), ny_.data(), nz_.data(), offsets_.data(), keys_.data(), from, n, x.x(), x.y(), x.z(), &k,
               &c);
  if (clearance) *clearance = c;
  return k;
}

std::vector<int> CellKeys::sides(const Vec3& x, int onPlane, int side, int onPlane2, int side2) const {
  std::vector<int> s(keys_.size());
  for (std::size_t j = 0; j < keys_.size(); ++j) {
    const double d = nx_[j] * x.x() + ny_[j] * x.y() + nz_[j] * x.z() - offsets_[j];
    s[j] = (int(j) == onPlane ? side > 0 : int(j) == onPlane2 ? side2 > 0 : d > 0) ? 1 : -1;
  }
  return s;
}

double scanSpacing(const Vec3& lo, const Vec3& hi, double voxel_mm, std::size_t planes, double work,
                   double max_points) {
  if (!(voxel_mm > 0)) throw std::invalid_argument("scanSpacing: voxel size must be positive");
  const Vec3 e = (hi - lo).cwiseMax(Vec3::Zero());
  double s = voxel_mm;
  for (;;) {
    const double points = (std::floor(e.x() / s) + 2) * (std::floor(e.y() / s) + 2) * (std::floor(e.z() / s) + 2);
    if (points * double(std::max<std::size_t>(planes, 1)) <= work && points <= max_points) return s;
    s *= 1.1;
  }
}

CellScan scanCells(const std::vector<Plane>& planes, const CellKeys& keys, const Vec3& lo, const Vec3& hi,
                   double spacing) {
  if (!(spacing > 0)) throw std::invalid_argument("scanCells: spacing must be positive");
  if (!(lo.array() < hi.array()).all()) throw std::invalid_argument("scanCells: empty box");
  CellScan out;
  out.lo = lo;
  out.hi = hi;
  out.half_diagonal_mm = spacing * std::sqrt(3.0) / 2;
  GridSpec& L = out.lattice;
  L.voxel = spacing;
  for (int a = 0; a < 3; ++a) {
    // Enough points to reach both faces; the overhang is split evenly.
    L.dims[a] = int(std::ceil((hi[a] - lo[a]) / spacing)) + 1;
    L.origin[a] = lo[a] - 0.5 * ((L.dims[a] - 1) * spacing - (hi[a] - lo[a]));
  }
  const int nx = L.dims[0], ny = L.dims[1], nz = L.dims[2];
  const std::size_t P = planes.size();
  const std::size_t n = std::size_t(L.count());
  std::vector<std::uint64_t> pointKey(n, 0);
  std::vector<float> pointDistance(n, -1.0f);  // −1: outside the box
  // Along a row, every plane's signed distance is a + b·i (floats: the scan's signs only differ from
  // exact ones within ~1e-6 of the box size of a plane, where D is that small anyway).
  const double tol = 1e-9 * (hi - lo).norm();
  tbb::parallel_for(0, ny * nz, [&](int row) {
    const int j = row % ny, k = row / ny;
    const Vec3 start = L.centre(0, j, k);
    if (start.y() < lo.y() - tol || start.y() > hi.y() + tol || start.z() < lo.z() - tol || start.z() > hi.z() + tol)
      return;
    std::vector<float> a(P), b(P);
    for (std::size_t p = 0; p < P; ++p) {
      a[p] = float(planes[p].signedDistance(start));
      b[p] = float(planes[p].normal.x() * spacing);
    }
    const std::size_t base = std::size_t(L.index(0, j, k));
    for (int i = 0; i < nx; ++i) {
      const double x = start.x() + i * spacing;
      if (x < lo.x() - tol || x > hi.x() + tol) continue;
      float d = std::numeric_limits<float>::infinity();
      std::uint64_t key = 0;
      const float fi = float(i);
      for (std::size_t p = 0; p < P; ++p) {
        const float v = a[p] + b[p] * fi;
        d = std::min(d, std::abs(v));
        key ^= keys.key(p) & (std::uint64_t(0) - std::uint64_t(v > 0));
      }
      pointKey[base + std::size_t(i)] = key;
      pointDistance[base + std::size_t(i)] = d;
    }
  });
  // Cells in scan order (sequential: ids do not depend on the threads).
  out.cell_of_point.assign(n, -1);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const std::size_t q = std::size_t(L.index(i, j, k));
        const float d = pointDistance[q];
        if (d < 0) continue;
        const auto [it, added] = out.index_of_key.emplace(pointKey[q], int(out.cells.size()));
        if (added) out.cells.push_back(ScannedCell{pointKey[q], -1.0, Vec3::Zero(), 0, false});
        ScannedCell& c = out.cells[std::size_t(it->second)];
        out.cell_of_point[q] = it->second;
        ++c.points;
        if (d > c.max_distance_mm) c.max_distance_mm = d, c.farthest = L.centre(i, j, k);
        const bool edge = i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1;
        // Lattice points beyond the box were skipped: the first and last inside count as the box.
        const Vec3 x = L.centre(i, j, k);
        if (edge || ((x - lo).array() < spacing).any() || ((hi - x).array() < spacing).any()) c.on_box = true;
      }
  return out;
}

}  // namespace xsect
