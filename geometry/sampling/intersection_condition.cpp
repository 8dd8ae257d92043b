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

/// R_C sampled at the centres of n[k] equal steps along each axis of the box [llo, llo + extent]
/// of the frame (mean, axes), with one empty layer around; the count of lattice points in C.
CellReconstructionTopology sampleCell(const std::vector<Plane>& planes, const std::vector<SectionDistanceField>& fields,
                                      const std::vector<int>& sides, const Vec3& lo, const Vec3& hi,
                                      const CellPolytope& cell, const Vec3& mean, const Eigen::Matrix3d& axes,
                                      const Vec3& llo, const Vec3& extent, const std::array<int, 3>& n,
                                      std::vector<std::uint8_t>* inside, GridSpec* grid) {
  CellReconstructionTopology out;
  grid->voxel = 1;  // only the lattice's combinatorics count (voxelBetti)
  for (int k = 0; k < 3; ++k) grid->dims[std::size_t(k)] = n[std::size_t(k)] + 2;
  const Vec3 step(extent[0] / n[0], extent[1] / n[1], extent[2] / n[2]);
  inside->assign(std::size_t(grid->count()), 0);
  for (int k = 1; k <= n[2]; ++k)
    for (int j = 1; j <= n[1]; ++j)
      for (int i = 1; i <= n[0]; ++i) {
        const Vec3 local = llo + step.cwiseProduct(Vec3(i - 0.5, j - 0.5, k - 0.5));
        const Vec3 x = mean + axes * local;
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
        if (fields[std::size_t(nearest)].sample(q.x(), q.y()) < 0) (*inside)[std::size_t(grid->index(i, j, k))] = 1;
      }
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
  // of a fan) fill their box.
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
  // Spacing: at most max_spacing_mm (the reconstruction's voxel), finer for a small cell (about
  // min_points over its box); at least kLayers steps along every axis, an even number so that no
  // layer lies on the bisector of two parallel facets (where the nearest facet is a tie).
  constexpr int kLayers = 4;
  double h = std::cbrt(std::max(extent.prod(), 0.0) / double(std::max(params.min_points, 8)));
  if (params.max_spacing_mm > 0) h = std::min(h, params.max_spacing_mm);
  if (!(h > 0) || !std::isfinite(h)) return out;
  // A cell whose lattice holds too few points, or none of R_C although the cell holds sections
  // (a piece of section narrower than the spacing), is sampled again 4 times finer.
  std::vector<std::uint8_t> inside;
  GridSpec grid;
  int in = 0;
  for (const double refine : {1.0, 0.25}) {
    std::array<int, 3> n{};
    double total = 1;
    for (int k = 0; k < 3; ++k) {
      const double steps = std::ceil(extent[k] / (refine * h));
      n[std::size_t(k)] = steps > 1e6 ? 1000000 : std::max(kLayers, int(steps) + int(steps) % 2);
      total *= double(n[std::size_t(k)]);
    }
    if (total > double(params.max_points)) break;  // too large to sample: not shown
    out = sampleCell(planes, fields, sides, lo, hi, cell, mean, axes, llo, extent, n, &inside, &grid);
    in = int(std::count(inside.begin(), inside.end(), std::uint8_t(1)));
    if (out.points_inside >= params.min_inside && in > 0) break;
  }
  if (out.points_inside < params.min_inside || in == 0) return out;
  out.sampled = true;
  if (in == out.points_inside) {  // all of the (convex) cell
    out.betti = {1, 0, 0};
    return out;
  }
  out.betti = voxelBetti(inside, grid);
  return out;
}

}  // namespace xsect
