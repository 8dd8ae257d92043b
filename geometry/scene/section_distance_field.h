// The function f_i of thesis ch. 1 §1.1 on one cutting plane: the signed Euclidean distance to the
// section-contours (negative inside the sections), sampled on a regular raster in plane coordinates
// and read back bilinearly. Exact at raster nodes within `band` of a contour; beyond the band only
// the sign is kept (value ±band). Outside the raster (farther than `band` from every section) the
// value is +band: the plane holds no section there.
#pragma once

#include <cmath>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct SectionDistanceField {
  Vec2 origin = Vec2::Zero();  ///< plane coordinates of node (0, 0), mm
  double step = 1.0;           ///< node spacing, mm
  int nu = 0, nv = 0;          ///< nodes along u and v (0 when the plane has no section)
  float band = 1.0f;           ///< clamp, mm
  std::vector<float> values;   ///< nu * nv, u fastest

  /// Bilinear value at plane coordinates (a, b) in mm.
  float sample(double a, double b) const {
    const double x = (a - origin.x()) / step, y = (b - origin.y()) / step;
    if (!(x >= 0.0 && y >= 0.0 && x <= nu - 1.0 && y <= nv - 1.0)) return band;
    int i = int(x), j = int(y);
    if (i >= nu - 1) i = nu - 2;
    if (j >= nv - 1) j = nv - 2;
    const float fx = float(x - i), fy = float(y - j);
    const float* r0 = &values[std::size_t(j) * nu + i];
    const float* r1 = r0 + nu;
    return (1 - fy) * ((1 - fx) * r0[0] + fx * r0[1]) + fy * ((1 - fx) * r1[0] + fx * r1[1]);
  }

  /// Bilinear value at (a, b) when the four nodes around it all hold exact distances (within the
  /// band): returns false, leaving *v alone, where a node is clamped or (a, b) is off the raster.
  bool sampleWithinBand(double a, double b, float* v) const {
    const double x = (a - origin.x()) / step, y = (b - origin.y()) / step;
    if (!(x >= 0.0 && y >= 0.0 && x <= nu - 1.0 && y <= nv - 1.0)) return false;
    int i = int(x), j = int(y);
    if (i >= nu - 1) i = nu - 2;
    if (j >= nv - 1) j = nv - 2;
    const float* r0 = &values[std::size_t(j) * nu + i];
    const float* r1 = r0 + nu;
    const float lim = band;
    if (!(std::abs(r0[0]) < lim && std::abs(r0[1]) < lim && std::abs(r1[0]) < lim &&
          std::abs(r1[1]) < lim))
      return false;
    const float fx = float(x - i), fy = float(y - j);
    *v = (1 - fy) * ((1 - fx) * r0[0] + fx * r0[1]) + fy * ((1 - fx) * r1[0] + fx * r1[1]);
    return true;
  }
};

/// @param sections  polygons with holes in plane coordinates (mm).
/// @param step      raster node spacing in mm (> 0).
/// @param band      distance beyond which only the sign is kept, mm (> step).
SectionDistanceField sectionDistanceField(const std::vector<Section>& sections, double step,
                                          double band);

}  // namespace xsect
