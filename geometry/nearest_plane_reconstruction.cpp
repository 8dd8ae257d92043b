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

  const auto doSuper = [&](int s, std::vector<int>& cand, std::vector<int>& sub,
                           std::vector<double>& lo) {
    const int bi = s % sx, bj = (s / sx) % sy, bk = s / (sx * sy);
    const int i0 = bi * kSuper, j0 = bj * kSuper, k0 = bk * kSuper;
    const int i1 = std::min(D[0], i0 + kSuper), j1 = std::min(D[1], j0 + kSuper),
              k1 = std::min(D[2], k0 + kSuper);
    Vec3 c, e;
    box(i0, j0, k0, i1, j1, k1, &c, &e);
    cull(rows, all, c, e, cand, lo);
    for (int kb = k0; kb < k1; kb += kBlock)
      for (int jb = j0; jb < j1; jb += kBlock)
        for (int ib = i0; ib < i1; ib += kBlock) {
          const int ie = std::min(i1, ib + kBlock), je = std::min(j1, jb + kBlock),
                    ke = std::min(k1, kb + kBlock);
          box(ib, jb, kb, ie, je, ke, &c, &e);
          cull(rows, cand, c, e, sub, lo);
          for (int k = kb; k < ke; ++k)
            for (int j = jb; j < je; ++j)
              for (int i = ib; i < ie; ++i) {
                const Vec3 x = grid.origin + h * Vec3(i, j, k);
                double best = std::numeric_limits<double>::infinity();
                int bp = sub.front();
                for (const int p : sub) {
                  const double d = std::abs(rows[p].s(x));
                  if (d < best) {
                    best = d;
                    bp = p;
                  }
                }
                const PlaneRow& r = rows[bp];
                const double a = r.ux * x.x() + r.uy * x.y() + r.uz * x.z() - r.uo;
                const double b = r.vx * x.x() + r.vy * x.y() + r.vz * x.z() - r.vo;
                const std::size_t idx = std::size_t(grid.index(i, j, k));
                out.value.values[idx] = fields[bp].sample(a, b);
                out.plane_distance[idx] = float(best);
                out.nearest_plane[idx] = bp;
              }
        }
  };

  // Chunks of super-boxes in parallel; progress between chunks, on the calling thread.
  const int chunk = std::max(1, supers / 20);
  for (int first = 0; first < supers; first += chunk) {
    const int last = std::min(supers, first + chunk);
    tbb::parallel_for(tbb::blocked_range<int>(first, last, 1), [&](const tbb::blocked_range<int>& r) {
      std::vector<int> cand, sub;
      std::vector<double> lo;
      cand.reserve(planes.size());
      for (int s = r.begin(); s != r.end(); ++s) doSuper(s, cand, sub, lo);
    });
    if (progress) progress(double(last) / supers);
  }
  return out;
}

}  // namespace xsect
