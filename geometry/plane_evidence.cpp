// Voxels next to the planes, certainly inside or outside (see plane_evidence.h).
#include "geometry/plane_evidence.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace xsect {

PlaneEvidence planeEvidence(const std::vector<CuttingPlane>& planes,
                            const std::vector<SectionDistanceField>& fields, const GridSpec& grid,
                            double near_mm, double margin_mm) {
  if (fields.size() != planes.size()) throw std::invalid_argument("one distance field per plane is required");
  if (!(near_mm >= 0) || !(margin_mm >= 0)) throw std::invalid_argument("evidence distances must be >= 0");
  const std::size_t n = std::size_t(grid.count());
  std::vector<float> best(n, std::numeric_limits<float>::infinity());
  std::vector<std::int32_t> owner(n, -1);
  const double h = grid.voxel;
  // Plane by plane (the order decides ties), each plane's voxels column by column along the axis
  // most normal to it: |n_a| >= 1/√3, so a column meets the slab |distance| <= near in at most
  // 2 near / (|n_a| h) + 1 voxels.
  for (std::size_t p = 0; p < planes.size(); ++p) {
    const Plane& P = planes[p].plane;
    int a = 0;
    for (int k = 1; k < 3; ++k)
      if (std::abs(P.normal[k]) > std::abs(P.normal[a])) a = k;
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const double na = P.normal[a];
    tbb::parallel_for(0, grid.dims[c], [&](int jc) {
      std::array<int, 3> idx{};
      for (int jb = 0; jb < grid.dims[b]; ++jb) {
        idx[b] = jb;
        idx[c] = jc;
        idx[a] = 0;
        // distance at index t along a: d0 + na h t
        const double d0 = P.signedDistance(grid.centre(idx[0], idx[1], idx[2]));
        const double t0 = (-near_mm - d0) / (na * h), t1 = (near_mm - d0) / (na * h);
        // Clamped as doubles: a plane far from the grid must not overflow the conversion.
        const int lo = int(std::clamp(std::floor(std::min(t0, t1)), 0.0, double(grid.dims[a]))),
                  hi = int(std::clamp(std::ceil(std::max(t0, t1)), -1.0, double(grid.dims[a] - 1)));
        for (int t = lo; t <= hi; ++t) {
          idx[a] = t;
          const double d = std::abs(d0 + na * h * t);
          if (d > near_mm) continue;
          const std::size_t q = std::size_t(grid.index(idx[0], idx[1], idx[2]));
          if (float(d) < best[q]) {
            best[q] = float(d);
            owner[q] = std::int32_t(p);
          }
        }
      }
    });
  }
  PlaneEvidence e;
  e.inside.assign(n, 0);
  e.outside.assign(n, 0);
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t q) {
    if (owner[q] < 0) return;
    const CuttingPlane& cp = planes[std::size_t(owner[q])];
    const int i = int(q % std::size_t(grid.dims[0])), j = int((q / std::size_t(grid.dims[0])) % std::size_t(grid.dims[1])),
              k = int(q / (std::size_t(grid.dims[0]) * std::size_t(grid.dims[1])));
    const Vec2 x = cp.plane.toPlane(grid.centre(i, j, k));
    const float f = fields[std::size_t(owner[q])].sample(x.x(), x.y());
    e.inside[q] = f <= -margin_mm && !cp.is_virtual;
    e.outside[q] = f >= margin_mm;
  });
  return e;
}

}  // namespace xsect
