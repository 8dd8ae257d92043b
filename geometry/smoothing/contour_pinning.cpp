// Pinning the section-contours on a sampled implicit function (see contour_pinning.h).
#include "geometry/smoothing/contour_pinning.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tuple>

#include "geometry/core/polygon.h"

namespace xsect {

namespace {

/// A voxel asked for by plane `plane`, at distance `t` (mm) from it.
struct Request {
  std::int64_t voxel;
  double t;
  std::size_t plane;
};

/// The voxels around each sample of plane p's contours where the trilinear reading of `field` is
/// more than `tol` inside; counts into `stats`.
void offSamples(const ScalarField& field, const std::vector<CuttingPlane>& planes, std::size_t p,
                double tol, const std::function<bool(std::size_t, double, double)>& observed,
                std::vector<Request>& out, ContourPinning& stats) {
  const GridSpec& g = field.grid;
  const CuttingPlane& plane = planes[p];
  const double step = 0.25 * g.voxel;
  const auto crowded = [&](const Vec3& x) {
    for (std::size_t q = 0; q < planes.size(); ++q)
      if (q != p && !planes[q].sections.empty() && std::abs(planes[q].plane.signedDistance(x)) < g.voxel)
        return true;
    return false;
  };
  const auto visit = [&](const Vec3& x) {
    const Vec3 u = (x - g.origin) / g.voxel;
    const int i = int(std::floor(u.x())), j = int(std::floor(u.y())), k = int(std::floor(u.z()));
    if (i < 0 || j < 0 || k < 0 || i + 1 >= g.dims[0] || j + 1 >= g.dims[1] || k + 1 >= g.dims[2]) return;
    const double fx = u.x() - i, fy = u.y() - j, fz = u.z() - k;
    double v = 0;
    for (int c = 0; c < 8; ++c) {
      const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
      v += (di ? fx : 1 - fx) * (dj ? fy : 1 - fy) * (dk ? fz : 1 - fz) * field.at(i + di, j + dj, k + dk);
    }
    ++stats.samples;
    stats.worst_before_mm = std::max(stats.worst_before_mm, std::abs(v));
    if (!(std::abs(v) > tol)) return;
    if (v > 0) {  // the solid does not reach the contour: pinning its rim alone would add a hole
      ++stats.samples_outside;
      return;
    }
    if (crowded(x)) {  // another plane within a voxel: the grid cannot hold both contours
      ++stats.samples_crowded;
      return;
    }
    ++stats.samples_pinned;
    for (int c = 0; c < 8; ++c) {
      const int ii = i + (c & 1), jj = j + ((c >> 1) & 1), kk = k + ((c >> 2) & 1);
      out.push_back({g.index(ii, jj, kk), std::abs(plane.plane.signedDistance(g.centre(ii, jj, kk))), p});
    }
  };
  for (const Vec2& a : contourSamples(plane.sections, step))
    if (!observed || observed(p, a.x(), a.y())) visit(plane.plane.toWorld(a));
}

}  // namespace

ContourPinning pinSectionContours(ScalarField& field, const std::vector<CuttingPlane>& planes,
                                  const std::function<double(std::size_t, double, double)>& plane_value,
                                  double tolerance_mm,
                                  const std::function<bool(std::size_t, double, double)>& observed) {
  if (!(tolerance_mm >= 0)) throw std::invalid_argument("contour pinning: the tolerance must be >= 0");
  if (std::int64_t(field.values.size()) != field.grid.count())
    throw std::invalid_argument("contour pinning: the field does not fill its grid");
  std::vector<std::vector<Request>> perPlane(planes.size());
  std::vector<ContourPinning> stats(planes.size());
  tbb::parallel_for(std::size_t(0), planes.size(), [&](std::size_t p) {
    offSamples(field, planes, p, tolerance_mm, observed, perPlane[p], stats[p]);
  });
  // Each voxel once, from the nearest plane that asks for it (ties: the lowest index).
  std::vector<Request> pinned;
  for (const auto& r : perPlane) pinned.insert(pinned.end(), r.begin(), r.end());
  std::sort(pinned.begin(), pinned.end(), [](const Request& a, const Request& b) {
    return std::tie(a.voxel, a.t, a.plane) < std::tie(b.voxel, b.t, b.plane);
  });
  pinned.erase(std::unique(pinned.begin(), pinned.end(),
                           [](const Request& a, const Request& b) { return a.voxel == b.voxel; }),
               pinned.end());
  const GridSpec& g = field.grid;
  std::vector<float> values(pinned.size());
  tbb::parallel_for(std::size_t(0), pinned.size(), [&](std::size_t q) {
    const std::int64_t v = pinned[q].voxel, row = std::int64_t(g.dims[0]) * g.dims[1];
    const int i = int(v % g.dims[0]), j = int((v / g.dims[0]) % g.dims[1]), k = int(v / row);
    const Vec2 ab = planes[pinned[q].plane].plane.toPlane(g.centre(i, j, k));
    values[q] = float(plane_value(pinned[q].plane, ab.x(), ab.y()));
  });
  for (std::size_t q = 0; q < pinned.size(); ++q) field.values[std::size_t(pinned[q].voxel)] = values[q];
  ContourPinning out;
  for (const auto& s : stats) {
    out.samples += s.samples;
    out.samples_pinned += s.samples_pinned;
    out.samples_outside += s.samples_outside;
    out.samples_crowded += s.samples_crowded;
    out.worst_before_mm = std::max(out.worst_before_mm, s.worst_before_mm);
  }
  out.voxels_pinned = std::int64_t(pinned.size());
  return out;
}

}  // namespace xsect
