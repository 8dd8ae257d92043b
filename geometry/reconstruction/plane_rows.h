// Cutting planes as rows of numbers for the per-voxel loops of methods 1 and Shepard: the signed
// distance s(x) = n.x - d, the plane coordinates a = u.x - uo, b = v.x - vo, and |n| (the
// half-width of s over a box of half-extent e is |n|.e, which the block culling uses).
#pragma once

#include <cmath>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct PlaneRow {
  double nx, ny, nz, d, ux, uy, uz, uo, vx, vy, vz, vo;
  double ax, ay, az;  ///< |n| componentwise
  double s(const Vec3& x) const { return nx * x.x() + ny * x.y() + nz * x.z() - d; }
  double dot(const PlaneRow& o) const { return nx * o.nx + ny * o.ny + nz * o.nz; }
};

inline std::vector<PlaneRow> planeRows(const std::vector<CuttingPlane>& planes) {
  std::vector<PlaneRow> rows(planes.size());
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const Plane& p = planes[i].plane;
    rows[i] = {p.normal.x(), p.normal.y(), p.normal.z(), p.normal.dot(p.origin),
               p.u.x(),      p.u.y(),      p.u.z(),      p.u.dot(p.origin),
               p.v.x(),      p.v.y(),      p.v.z(),      p.v.dot(p.origin),
               std::abs(p.normal.x()), std::abs(p.normal.y()), std::abs(p.normal.z())};
  }
  return rows;
}

}  // namespace xsect
