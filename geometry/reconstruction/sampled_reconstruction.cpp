// Method 1 on a grid, with open ends closed and the sampled topology repaired
// (see sampled_reconstruction.h).
#include "geometry/reconstruction/sampled_reconstruction.h"

#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "geometry/arrangement/end_planes.h"
#include "geometry/reconstruction/nearest_plane_reconstruction.h"
#include "geometry/reconstruction/section_voronoi_reconstruction.h"
#include "geometry/reconstruction/section_distance_field.h"

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
  // R' may reach the end planes themselves (a lift ends on ∂C): t <= m.
  // Two layers of outside voxels close the surface.
  L.grid.voxel = h;
  const double reachOut =
      (params.method == ReconstructionMethod::section_voronoi ? 1.0 : 0.5) * L.end_margin_mm + h;
  const Vec3 boxLo = L.sections_min - Vec3::Constant(reachOut),
             boxHi = L.sections_max + Vec3::Constant(reachOut);
  L.grid.origin = boxLo - Vec3::Constant(2 * h);
  double count = 1;
  for (int a = 0; a < 3; ++a) {
    const double n = std::ceil((boxHi[a] - boxLo[a]) / h) + 5;
    count *= n;
    L.grid.dims[a] = n < 2147483647.0 ? int(n) : 0;
  }
  if (count > 2147483647.0)
    throw std::invalid_argument("grid of " + std::to_string(std::int64_t(count)) +
                                " voxels is too large: increase reconstruction.voxel_size_mm");
  return L;
}

SampledReconstruction reconstructOnGrid(const std::vector<CuttingPlane>& realPlanes,
                                              const ReconstructionParams& params,
                                              const std::function<void(double)>& progress) {
  const ReconstructionLayout layout = reconstructionLayout(realPlanes, params);
  const double h = params.voxel_mm;
  const GridSpec& grid = layout.grid;
  SampledReconstruction out;
  out.end_margin_auto = layout.end_margin_auto;
  out.end_margin_mm = layout.end_margin_mm;
  out.end_planes = endPlanes(layout.sections_min, layout.sections_max, out.end_margin_mm);
  std::vector<CuttingPlane> planes = realPlanes;
  planes.insert(planes.end(), out.end_planes.begin(), out.end_planes.end());

  // f_i rasters, one per plane (virtual planes hold no section).
  const double band = params.band_voxels * h;
  std::vector<SectionDistanceField> fields(planes.size());
  tbb::parallel_for(std::size_t(0), planes.size(), [&](std::size_t i) {
    const double step = planes[i].pixel_mm > 0 ? std::min(planes[i].pixel_mm, 0.5 * h) : 0.5 * h;
    fields[i] = sectionDistanceField(planes[i].sections, step, std::max(band, 3 * step));
  });

  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t n = std::size_t(grid.count());
  ScalarField value;
  std::vector<float> planeDistance;
  std::vector<int> nearestPlane;
  out.section_plane.assign(n, -1);
  if (params.method == ReconstructionMethod::nearest_plane) {
    NearestPlaneField npf = nearestPlaneReconstruction(planes, fields, grid, progress);
    value = std::move(npf.value);
    planeDistance = std::move(npf.plane_distance);
    nearestPlane = std::move(npf.nearest_plane);
    for (std::size_t q = 0; q < n; ++q)
      if (value.values[q] < 0) {
        out.section_plane[q] = nearestPlane[q];
        out.max_lift_mm = std::max(out.max_lift_mm, double(planeDistance[q]));
      }
  } else {
    SectionVoronoiParams vp;
    vp.slab_mm = params.slab_voxels * h;
    SectionVoronoiField svf = sectionVoronoiReconstruction(planes, fields, grid, vp, progress);
    value = std::move(svf.value);
    planeDistance = std::move(svf.plane_distance);
    nearestPlane = std::move(svf.nearest_plane);
    out.section_plane = std::move(svf.section_plane);
    for (std::size_t q = 0; q < n; ++q)
      if (value.values[q] < 0) out.max_lift_mm = std::max(out.max_lift_mm, double(svf.lift_height[q]));
    out.exact_face_tests = svf.exact_face_tests;
    out.search_restarts = svf.search_restarts;
  }
  out.evaluate_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // Evidence for the repair: voxels next to a plane (within half a voxel diagonal), clearly inside
  // or clearly outside its sections (by half a voxel). Method 2 marks voxels that no plane's
  // sections can reach by projection (nearest_plane -1) as outside evidence too.
  const float near = float(0.5 * std::sqrt(3.0) * h), margin = float(0.5 * h);
  std::vector<std::uint8_t> inAnchor(n), outAnchor(n);
  out.inside.resize(n);
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t q) {
    const float v = value.values[q];
    out.inside[q] = v < 0;
    if (nearestPlane[q] < 0) {
      outAnchor[q] = 1;
      return;
    }
    const bool next = planeDistance[q] <= near;
    inAnchor[q] = next && v <= -margin && !planes[std::size_t(nearestPlane[q])].is_virtual;
    outAnchor[q] = next && v >= margin;
  });
  out.raw_inside = out.inside;
  out.repair = repairSampledTopology(out.inside, inAnchor, outAnchor, grid);

  // The field for meshing: the evaluated values, with their sign forced to the repaired set.
  out.field = std::move(value);
  imposeSolid(out.field, out.inside, float(0.05 * h));
  std::int64_t inside = 0;
  for (std::size_t q = 0; q < n; ++q) {
    if (out.section_plane[q] >= int(realPlanes.size())) out.section_plane[q] = -1;
    inside += out.inside[q];
  }
  out.voxels_inside = inside;
  out.fields = std::move(fields);
  out.voxel_betti = voxelBetti(out.inside, grid);
  return out;
}

}  // namespace xsect
