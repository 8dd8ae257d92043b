// The Intersection Condition shown on the data, per cell (see intersection_condition.h).
#include "geometry/sampling/intersection_condition.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <Eigen/Eigenvalues>

#include "geometry/core/digital_topology.h"
#include "geometry/sampling/cell_polytope.h"

namespace xsect {

namespace {

/// R_C sampled on the lattice of spacing h over the box [llo, llo + extent] of the frame (mean,
/// axes); `inside` and the count of lattice points in C (betti left zero).
CellReconstructionTopology sampleCell(const std::vector<Plane>& planes, const std::vector<SectionDistanceField>& fields,
                                      const std::vector<int>& sides, const Vec3& lo, const Vec3& hi,
                                      const CellPolytope& cell, const Vec3& mean, const Eigen::Matrix3d& axes,
                                      const Vec3& llo, const Vec3& extent, double h,
                                      std::vector<std::uint8_t>* insideOut, GridSpec* gridOut) {
  CellReconstructionTopology out;
  GridSpec grid;
  grid.voxel = h;
  for (int k = 0; k < 3; ++k) grid.dims[std::size_t(k)] = std::max(1, int(std::ceil(extent[k] / h))) + 2;
  // The inner points centred on the box; lattice point (0, 0, 0) one spacing before the first.
  const Vec3 span = h * Vec3(grid.dims[0] - 3, grid.dims[1] - 3, grid.dims[2] - 3);
  const Vec3 first = llo + 0.5 * (extent - span);
  std::vector<std::uint8_t> inside(std::size_t(grid.count()), 0);
  for (int k = 1; k + 1 < grid.dims[2]; ++k)
    for (int j = 1; j + 1 < grid.dims[1]; ++j)
      for (int i = 1; i + 1 < grid.dims[0]; ++i) {
        const Vec3 x = mean + axes * (first + h * Vec3(i - 1, j - 1, k - 1));
        // In C, and the plane of C nearest to x (its projection lies on that facet).
        int nearest = -1;
        double best = 0;
        bool in = true;
        for (const int p : cell.planes) {
          const double d = double(sides[std::size_t(p)]) * planes[std::size_t(p)].signedDistance(x);
          if (d < 0) {
            in = false;
            break;
          }
          if (nearest < 0 || d < best) nearest = p, best = d;
        }
        for (int a = 0; a < 3 && in; ++a) in = x[a] >= lo[a] && x[a] <= hi[a];
        if (!in || nearest < 0) continue;
        ++out.points_inside;
        if (std::size_t(nearest) >= fields.size()) continue;
        const Vec2 q = planes[std::size_t(nearest)].toPlane(x);
        if (fields[std::size_t(nearest)].sample(q.x(), q.y()) < 0) inside[std::size_t(grid.index(i, j, k))] = 1;
      }
  out.spacing_mm = h;
  *insideOut = std::move(inside);
  *gridOut = grid;
  return out;
}

}  // namespace

CellReconstructionTopology cellReconstructionTopology(const std::vector<Plane>& planes,
                                                      const std::vector<SectionDistanceField>& fields,
                                                      const std::vector<int>& sides, const Vec3& interior,
                                                      const Vec3& lo, const Vec3& hi,
                                                      const CellTopologyParams& params) {
  CellReconstructionTopology out;
  const CellPolytope cell = cellPolytope(planes, sides, interior, lo, hi);
  if (cell.empty()) return out;
  // The lattice lies in the frame of the vertices' principal axes, so that thin cells (the wedges
  // of a fan) fill their box; cubes of side h at about `lattice_points` points over the box, plus
  // one empty layer around (the closed cubes of R_C never touch the grid's border).
  Vec3 mean = Vec3::Zero();
  for (const Vec3& v : cell.vertices) mean += v;
  mean /= double(cell.vertices.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Vec3& v : cell.vertices) cov += (v - mean) * (v - mean).transpose();
  const Eigen::Matrix3d axes = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors();
  Vec3 llo = Vec3::Constant(1e300), lhi = Vec3::Constant(-1e300);
  for (const Vec3& v : cell.vertices) {
    const Vec3 l = axes.transpose() * (v - mean);
    llo = llo.cwiseMin(l), lhi = lhi.cwiseMax(l);
  }
  const Vec3 extent = lhi - llo;
  // About `points` lattice points: h such that the product over the axes of max(1, extent / h) is
  // `points` (an axis thinner than h holds one layer). A cell holding too few is sampled once more,
  // 8 times finer.
  std::vector<std::uint8_t> inside;
  GridSpec grid;
  for (const int points : {std::max(params.lattice_points, 8), 8 * std::max(params.lattice_points, 8)}) {
    double h = 0, product = 1;
    int axesLeft = 3;
    std::array<bool, 3> thin{false, false, false};
    for (int round = 0; round < 3; ++round) {
      product = 1;
      axesLeft = 0;
      for (int k = 0; k < 3; ++k)
        if (!thin[std::size_t(k)]) product *= std::max(extent[k], 1e-300), ++axesLeft;
      h = std::pow(product / double(points), 1.0 / double(axesLeft));
      bool changed = false;
      for (int k = 0; k < 3; ++k)
        if (!thin[std::size_t(k)] && extent[k] < h && axesLeft > 1) thin[std::size_t(k)] = changed = true;
      if (!changed) break;
    }
    if (!(h > 0) || !std::isfinite(h)) return out;
    out = sampleCell(planes, fields, sides, lo, hi, cell, mean, axes, llo, extent, h, &inside, &grid);
    if (out.points_inside >= params.min_inside) break;
  }
  if (out.points_inside < params.min_inside) {
    out.sampled = false;
    return out;
  }
  out.sampled = true;
  // R_C empty, or all of the (convex) cell: nothing to count.
  const int in = int(std::count(inside.begin(), inside.end(), std::uint8_t(1)));
  if (in == 0 || in == out.points_inside) {
    out.betti = {in > 0 ? 1 : 0, 0, 0};
    return out;
  }
  out.betti = voxelBetti(inside, grid);
  return out;
}

}  // namespace xsect
