// Voxels next to the planes, certainly inside or outside (see plane_evidence.h).
#include "geometry/reconstruction/plane_evidence.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace xsect {

PlaneEvidence planeEvidence(const std::vector<CuttingPlane>& planes,
                            const std::vector<SectionDistanceField>& fields, const GridSpec& grid,
                            double near_mm, double margin_mm, const std::vector<ObservedPiece>* pieces) {
  if (pieces && pieces->size() != planes.size()) throw std::invalid_argument("one observed piece per plane is required");
  if (fields.size() != planes.size()) throw std::invalid_argument("one distance field per plane is required");
  if (!(near_mm >= 0) || !(margin_mm >= 0)) throw std::invalid_argument("evidence distances must be >= 0");
  const std::size_t n = std::size_t(grid.count());
  const double h = grid.voxel;
  // Calls visit(q, d) for every voxel q whose centre is within near_mm of plane p (d: distance),
  // column by column along the axis most normal to the plane: |n_a| >= 1/√3, so a column meets the
  // slab in at most 2 near / (|n_a| h) + 1 voxels. Columns are disjoint: visit may write voxel q.
  // Whether voxel idx's projection lies in plane p's observed piece.
  const auto observedAt = [&](std::size_t p, const std::array<int, 3>& idx) {
    if (!pieces || (*pieces)[p].whole) return true;
    const Vec2 x = planes[p].plane.toPlane(grid.centre(idx[0], idx[1], idx[2]));
    return (*pieces)[p].holds(x.x(), x.y());
  };
  const auto forVoxelsNear = [&](std::size_t p, const auto& visit) {
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
        const double d0 = P.signedDistance(grid.centre(idx[0], idx[1], idx[2]));  // + na h t at index t
        const double t0 = (-near_mm - d0) / (na * h), t1 = (near_mm - d0) / (na * h);
        // Clamped as doubles: a plane far from the grid must not overflow the conversion.
        const int lo = int(std::clamp(std::floor(std::min(t0, t1)), 0.0, double(grid.dims[a]))),
                  hi = int(std::clamp(std::ceil(std::max(t0, t1)), -1.0, double(grid.dims[a] - 1)));
        for (int t = lo; t <= hi; ++t) {
          idx[a] = t;
          const double d = std::abs(d0 + na * h * t);
          if (d <= near_mm && observedAt(p, idx)) visit(std::size_t(grid.index(idx[0], idx[1], idx[2])), d, idx);
        }
      }
    });
  };
  // Pass 1: the distance to the nearest plane. Pass 2: the planes within a millionth of a voxel of
  // it (coincident planes: two observations of one plane) decide together, inside when one of
  // them says inside, outside when all say outside (a plane listed again without its section must
  // not erase it). Two passes, so that the result does not depend on the planes' order.
  std::vector<double> best(n, std::numeric_limits<double>::infinity());
  for (std::size_t p = 0; p < planes.size(); ++p)
    forVoxelsNear(p, [&](std::size_t q, double d, const std::array<int, 3>&) { best[q] = std::min(best[q], d); });
  const double tie = 1e-6 * h;
  PlaneEvidence e;
  e.inside.assign(n, 0);
  e.outside.assign(n, 0);
  std::vector<std::uint8_t> seen(n, 0);
  for (std::size_t p = 0; p < planes.size(); ++p)
    forVoxelsNear(p, [&](std::size_t q, double d, const std::array<int, 3>& idx) {
      if (d > best[q] + tie) return;
      const Vec2 x = planes[p].plane.toPlane(grid.centre(idx[0], idx[1], idx[2]));
      const float f = fields[p].sample(x.x(), x.y());
      const bool in = f <= -margin_mm && !planes[p].is_virtual, out = f >= margin_mm;
      e.inside[q] = e.inside[q] || in;
      e.outside[q] = seen[q] ? (e.outside[q] && out) : out;
      seen[q] = 1;
    });
  return e;
}

}  // namespace xsect
