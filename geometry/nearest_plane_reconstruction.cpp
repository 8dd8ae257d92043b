// Method 1 with block culling of planes (see nearest_plane_reconstruction.h).
#include "geometry/nearest_plane_reconstruction.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace xsect {

namespace {

struct PlaneRow {  // s(x) = n.x - d; plane coordinates a = u.x - uo, b = v.x - vo
  double nx, ny, nz, d, ux, uy, uz, uo, vx, vy, vz, vo;
  double s(const Vec3& x) const { return nx * x.x() + ny * x.y() + nz * x.z() - d; }
};

/// Planes of `from` that may be nearest somewhere in the box [c - e, c + e].
void cull(const std::vector<PlaneRow>& rows, const std::vector<int>& from, const Vec3& c,
          const Vec3& e, std::vector<int>& out, std::vector<double>& lo) {
  double minHi = std::numeric_limits<double>::infinity();
  lo.resize(from.size());
  for (std::size_t k = 0; k < from.size(); ++k) {
    const PlaneRow& p = rows[from[k]];
    const double r = std::abs(p.nx) * e.x() + std::abs(p.ny) * e.y() + std::abs(p.nz) * e.z();
    const double a = std::abs(p.s(c));
    lo[k] = std::max(0.0, a - r);
    minHi = std::min(minHi, a + r);
  }
  out.clear();
  for (std::size_t k = 0; k < from.size(); ++k)
    if (lo[k] <= minHi) out.push_back(from[k]);
}

}  // namespace

NearestPlaneField nearestPlaneReconstruction(const std::vector<CuttingPlane>& planes,
                                             const std::vector<SectionDistanceField>& fields,
                                             const GridSpec& grid,
                                             const std::function<void(double)>& progress) {
  if (planes.empty()) throw std::invalid_argument("method 1: no cutting plane");
  if (fields.size() != planes.size())
    throw std::invalid_argument("method 1: one distance raster per plane is required");
  if (!(grid.voxel > 0)) throw std::invalid_argument("method 1: voxel size must be positive");
  std::vector<PlaneRow> rows(planes.size());
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const Plane& p = planes[i].plane;
    rows[i] = {p.normal.x(), p.normal.y(), p.normal.z(), p.normal.dot(p.origin),
               p.u.x(),      p.u.y(),      p.u.z(),      p.u.dot(p.origin),
               p.v.x(),      p.v.y(),      p.v.z(),      p.v.dot(p.origin)};
  }
  std::vector<int> all(planes.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = int(i);

  NearestPlaneField out;
  out.value.grid = grid;
  const std::size_t n = std::size_t(grid.count());
  out.value.values.resize(n);
  out.plane_distance.resize(n);
  out.nearest_plane.resize(n);

  constexpr int kSuper = 32, kBlock = 8;
  const auto& D = grid.dims;
  const int sx = (D[0] + kSuper - 1) / kSuper, sy = (D[1] + kSuper - 1) / kSuper,
            sz = (D[2] + kSuper - 1) / kSuper;
  const int supers = sx * sy * sz;
  const double h = grid.voxel;

  const auto box = [&](int i0, int j0, int k0, int i1, int j1, int k1, Vec3* c, Vec3* e) {
    const Vec3 a = grid.centre(i0, j0, k0), b = grid.centre(i1 - 1, j1 - 1, k1 - 1);
    *c = 0.5 * (a + b);
    *e = 0.5 * (b - a);
  };

  // Pass 1: planes that may be nearest in each 32³ super-box.
  std::vector<std::vector<int>> superCand(supers);
  tbb::parallel_for(0, supers, [&](int s) {
    const int bi = s % sx, bj = (s / sx) % sy, bk = s / (sx * sy);
    const int i0 = bi * kSuper, j0 = bj * kSuper, k0 = bk * kSuper;
    Vec3 c, e;
    box(i0, j0, k0, std::min(D[0], i0 + kSuper), std::min(D[1], j0 + kSuper),
        std::min(D[2], k0 + kSuper), &c, &e);
    std::vector<double> lo;
    cull(rows, all, c, e, superCand[s], lo);
  });

  // Pass 2: 8³ boxes cull from their super-box's list; voxels scan the survivors, with each
  // candidate's distance updated incrementally along the box.
  const int bx = (D[0] + kBlock - 1) / kBlock, by = (D[1] + kBlock - 1) / kBlock,
            bz = (D[2] + kBlock - 1) / kBlock;
  const int blocks = bx * by * bz;
  const auto doBlock = [&](int b, std::vector<int>& sub, std::vector<double>& lo,
                           std::vector<double>& s0) {
    const int ib = (b % bx) * kBlock, jb = ((b / bx) % by) * kBlock, kb = (b / (bx * by)) * kBlock;
    const int ie = std::min(D[0], ib + kBlock), je = std::min(D[1], jb + kBlock),
              ke = std::min(D[2], kb + kBlock);
    const int s = (ib / kSuper) + sx * ((jb / kSuper) + sy * (kb / kSuper));
    Vec3 c, e;
    box(ib, jb, kb, ie, je, ke, &c, &e);
    cull(rows, superCand[s], c, e, sub, lo);
    // 2³ boxes inside the 8³ box cull again from its list: with dense near-parallel planes
    // (freehand sweeps) the 8³ list holds every plane within ~2 box widths; the 2³ list ~4.
    const std::vector<int> blockCand = sub;
    std::vector<int> tiny;
    for (int k2 = kb; k2 < ke; k2 += 2)
      for (int j2 = jb; j2 < je; j2 += 2)
        for (int i2 = ib; i2 < ie; i2 += 2) {
          const int ie2 = std::min(ie, i2 + 2), je2 = std::min(je, j2 + 2), ke2 = std::min(ke, k2 + 2);
          box(i2, j2, k2, ie2, je2, ke2, &c, &e);
          cull(rows, blockCand, c, e, tiny, lo);
          const Vec3 x0 = grid.centre(i2, j2, k2);
          s0.resize(tiny.size());
          for (std::size_t q = 0; q < tiny.size(); ++q) s0[q] = rows[tiny[q]].s(x0);
          for (int k = k2; k < ke2; ++k)
            for (int j = j2; j < je2; ++j)
              for (int i = i2; i < ie2; ++i) {
                const double di = (i - i2) * h, dj = (j - j2) * h, dk = (k - k2) * h;
                double best = std::numeric_limits<double>::infinity();
                int bq = 0;
                for (std::size_t q = 0; q < tiny.size(); ++q) {
                  const PlaneRow& r = rows[tiny[q]];
                  const double d = std::abs(s0[q] + r.nx * di + r.ny * dj + r.nz * dk);
                  if (d < best) {
                    best = d;
                    bq = int(q);
                  }
                }
                const int bp = tiny[bq];
                const PlaneRow& r = rows[bp];
                const Vec3 x = x0 + Vec3(di, dj, dk);
                const double a = r.ux * x.x() + r.uy * x.y() + r.uz * x.z() - r.uo;
                const double bb = r.vx * x.x() + r.vy * x.y() + r.vz * x.z() - r.vo;
                const std::size_t idx = std::size_t(grid.index(i, j, k));
                out.value.values[idx] = fields[bp].sample(a, bb);
                out.plane_distance[idx] = float(best);
                out.nearest_plane[idx] = bp;
              }
        }
  };
  const int chunk = std::max(256, blocks / 16);
  for (int first = 0; first < blocks; first += chunk) {
    const int last = std::min(blocks, first + chunk);
    tbb::parallel_for(tbb::blocked_range<int>(first, last, 16), [&](const tbb::blocked_range<int>& r) {
      std::vector<int> sub;
      std::vector<double> lo, s0;
      for (int b = r.begin(); b != r.end(); ++b) doBlock(b, sub, lo, s0);
    });
    if (progress) progress(double(last) / blocks);
  }
  return out;
}

}  // namespace xsect
