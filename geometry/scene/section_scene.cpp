// The section scene: layout, end planes and distance rasters (see section_scene.h).
#include "geometry/scene/section_scene.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "geometry/scene/end_planes.h"

namespace xsect {

ReconstructionLayout reconstructionLayout(const std::vector<CuttingPlane>& planes,
                                          const ReconstructionParams& params) {
  if (!(params.voxel_mm > 0)) throw std::invalid_argument("voxel size must be positive");
  ReconstructionLayout L;
  if (!sectionBounds(planes, &L.sections_min, &L.sections_max))
    throw std::invalid_argument("no section in any slice: nothing to reconstruct");
  const double h = params.voxel_mm;
  L.end_margin_auto = !params.end_margin_mm;
  L.end_margin_mm = params.end_margin_mm ? *params.end_margin_mm
                                         : std::max(2.0 * h, automaticEndMargin(planes, 10.0 * h));
  // Grid: R lies within half the end margin of the sections' bounds. A point of R at distance t
  // beyond the bounds (along an axis) projects onto a section inside them, so its nearest plane is
  // at least t away, while the end plane beyond it is m - t away (Def. 15-16): t <= m / 2.
  // R' may reach the end planes themselves (a lift ends on ∂C): t <= m. R'' (method 3), a union
  // of tetrahedra on section-vertices, lies in the sections' convex hull: t <= 0.
  // Two layers of outside voxels close the surface.
  L.grid.voxel = h;
  const double reachOut =
      (params.method == ReconstructionMethod::section_voronoi ? 1.0 : 0.5) * L.end_margin_mm + h;
  const Vec3 boxLo = L.sections_min - Vec3::Constant(reachOut),
             boxHi = L.sections_max + Vec3::Constant(reachOut);
  L.grid.origin = boxLo - Vec3::Constant(2 * h);
  // The solid is kept by blocks (block_grid.h), so the count itself is not bounded by an array's
  // size; what would not fit in memory is refused before allocating (solid_memory.h). 2^40 voxels
  // (4 TB as bytes, 2^31 blocks) is beyond any machine this runs on.
  double count = 1;
  for (int a = 0; a < 3; ++a) {
    const double n = std::ceil((boxHi[a] - boxLo[a]) / h) + 5;
    count *= n;
    L.grid.dims[a] = n < 2147483647.0 ? int(n) : 0;
  }
  if (count > 1099511627776.0 || !(count >= 1))
    throw std::invalid_argument("grid of " + std::to_string(count) +
                                " voxels is too large: increase reconstruction.voxel_size_mm");
  return L;
}

double rasterStep(double pixel_mm, double voxel_mm) {
  // The pixel's scale where it is within a few voxels, never finer than an eighth of a voxel:
  // each contour edge fills the nodes within the band, (2 band / step)^2 of them, so a node
  // spacing set by the pixel alone made the cost grow with (voxel / pixel)^2 (issue 48: poses in
  // metres with a voxel of 0.4 took hours here). At h/8 the bilinear reading is exact to well
  // under a voxel, which is what the grid can hold.
  return pixel_mm > 0 ? std::min(0.5 * voxel_mm, std::max(pixel_mm, voxel_mm / 8)) : 0.5 * voxel_mm;
}

SectionScene sectionScene(const std::vector<CuttingPlane>& realPlanes, const ReconstructionParams& params) {
  return sectionScene(realPlanes, params, reconstructionLayout(realPlanes, params));
}

SectionScene sectionScene(const std::vector<CuttingPlane>& realPlanes, const ReconstructionParams& params,
                          const ReconstructionLayout& layout) {
  SectionScene s;
  s.params = params;
  s.layout = layout;
  s.planes = realPlanes;
  s.real_planes = realPlanes.size();
  const std::vector<CuttingPlane> ends =
      endPlanes(s.layout.sections_min, s.layout.sections_max, s.layout.end_margin_mm);
  s.planes.insert(s.planes.end(), ends.begin(), ends.end());

  s.pieces = observedPieces(s.planes, params.planes == PlaneExtent::observed);
  const double h = params.voxel_mm, band = params.band_voxels * h;
  s.fields.resize(s.planes.size());
  tbb::parallel_for(std::size_t(0), s.planes.size(), [&](std::size_t i) {
    const CuttingPlane& P = s.planes[i];
    const double step = rasterStep(P.pixel_mm, h);
    s.fields[i] = sectionDistanceField(P.sections, step, std::max(band, 3 * step));
  });
  markSectionsClearOfEdges(s.pieces, s.fields);
  return s;
}

}  // namespace xsect
