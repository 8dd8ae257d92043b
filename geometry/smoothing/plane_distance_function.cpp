// f_i on a whole plane: band raster near the contours, EDT-extended coarse raster beyond
// (see plane_distance_function.h).
#include "geometry/smoothing/plane_distance_function.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "geometry/core/polygon.h"

namespace xsect {

namespace {

/// Bounding rectangle, in plane coordinates, of the plane's intersection with the box of voxel
/// centres of `grid`; false when the plane misses the box.
bool planeInGrid(const Plane& plane, const GridSpec& grid, Vec2* lo, Vec2* hi) {
  const Vec3 a = grid.origin;
  const Vec3 b = grid.origin + grid.voxel * Vec3(grid.dims[0] - 1, grid.dims[1] - 1, grid.dims[2] - 1);
  bool any = false;
  *lo = Vec2::Constant(1e300);
  *hi = Vec2::Constant(-1e300);
  for (int axis = 0; axis < 3; ++axis)
    for (int c = 0; c < 4; ++c) {  // the 4 box edges along `axis`
      Vec3 p = a, q;
      const int o1 = (axis + 1) % 3, o2 = (axis + 2) % 3;
      p[o1] = (c & 1) ? b[o1] : a[o1];
      p[o2] = (c & 2) ? b[o2] : a[o2];
      q = p;
      p[axis] = a[axis];
      q[axis] = b[axis];
      const double sp = plane.signedDistance(p), sq = plane.signedDistance(q);
      if ((sp > 0 && sq > 0) || (sp < 0 && sq < 0)) continue;
      const auto add = [&](const Vec3& x) {
        const Vec2 y = plane.toPlane(x);
        *lo = lo->cwiseMin(y);
        *hi = hi->cwiseMax(y);
        any = true;
      };
      if (sp == sq) {  // the edge lies in the plane
        add(p);
        add(q);
      } else {
        add(p + (sp / (sp - sq)) * (q - p));
      }
    }
  return any;
}

}  // namespace

PlaneDistanceFunction planeDistanceFunction(const SectionDistanceField& near, const Plane& plane,
                                            const GridSpec& grid, double cap) {
  if (!(cap > 0) || !std::isfinite(cap))
    throw std::invalid_argument("distance cap must be positive and finite");
  PlaneDistanceFunction f;
  f.cap = float(cap);
  f.far.band = float(cap);  // the raster's outside value
  f.far.step = 2 * near.step;
  Vec2 lo, hi;
  if (near.nu < 2 || near.nv < 2 || !planeInGrid(plane, grid, &lo, &hi)) return f;
  // Beyond the band raster grown by the cap every value is the cap: no need to store it.
  const double s = near.step, S = 2 * s, grow = cap + S;
  lo = lo.cwiseMax(near.origin - Vec2::Constant(grow));
  hi = hi.cwiseMin(near.origin + s * Vec2(near.nu - 1, near.nv - 1) + Vec2::Constant(grow));
  if (!(lo.x() <= hi.x() && lo.y() <= hi.y())) return f;
  // Coarse nodes are the band raster's even nodes (extended beyond it): (I, J) -> (i0 + 2I, j0 + 2J).
  const int i0 = 2 * int(std::floor((lo.x() - near.origin.x()) / S)) ;
  const int j0 = 2 * int(std::floor((lo.y() - near.origin.y()) / S));
  f.far.origin = near.origin + s * Vec2(i0, j0);
  f.far.nu = int(std::ceil((hi.x() - f.far.origin.x()) / S)) + 2;
  f.far.nv = int(std::ceil((hi.y() - f.far.origin.y()) / S)) + 2;
  const int NU = f.far.nu, NV = f.far.nv;
  cv::Mat seeds(NV, NU, CV_8U);
  std::vector<float> nodeValue(std::size_t(NU) * NV);
  std::vector<std::int8_t> sign(nodeValue.size(), 1);
  const float b = near.band;
  bool anySeed = false;
  for (int J = 0; J < NV; ++J)
    for (int I = 0; I < NU; ++I) {
      const int i = i0 + 2 * I, j = j0 + 2 * J;
      std::uint8_t seed = 255;
      if (i >= 0 && j >= 0 && i < near.nu && j < near.nv) {
        const float v = near.node(i, j);
        sign[std::size_t(J) * NU + I] = v < 0 ? -1 : 1;
        if (std::abs(v) < b) {
          seed = 0;
          anySeed = true;
          nodeValue[std::size_t(J) * NU + I] = v;
        }
      }
      seeds.at<std::uint8_t>(J, I) = seed;
    }
  if (!anySeed) {  // contours far outside the grid: the plane is "far outside" everywhere here
    f.far.nu = f.far.nv = 0;
    return f;
  }
  cv::Mat dist;
  cv::distanceTransform(seeds, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  std::vector<float> values(nodeValue.size());
  const double half = S / std::sqrt(2.0);
  for (int J = 0; J < NV; ++J)
    for (int I = 0; I < NU; ++I) {
      const std::size_t q = std::size_t(J) * NU + I;
      double d;
      if (seeds.at<std::uint8_t>(J, I) == 0) {
        d = nodeValue[q];
      } else {
        d = sign[q] * std::max(double(b), b + S * double(dist.at<float>(J, I)) - half);
      }
      values[q] = float(std::min(d, cap));
    }
  f.far = SectionDistanceField::fromNodes(f.far.origin, f.far.step, NU, NV, f.far.band, values);
  return f;
}

double defaultDistanceCap(const std::vector<CuttingPlane>& planes, double fallback) {
  double areaMax = 0;
  for (const auto& p : planes)
    for (const auto& sec : p.sections) areaMax = std::max(areaMax, sectionArea(sec));
  return areaMax > 0 ? std::sqrt(areaMax / M_PI) : fallback;
}

}  // namespace xsect
