// Method 1 or 2 on the scene's grid, with the sampled topology repaired
// (see sampled_reconstruction.h).
#include "geometry/reconstruction/sampled_reconstruction.h"

#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>

#include "geometry/reconstruction/nearest_plane_reconstruction.h"
#include "geometry/reconstruction/section_voronoi_reconstruction.h"

namespace xsect {

SampledReconstruction reconstructOnGrid(const SectionScene& scene, const std::function<void(double)>& progress) {
  const ReconstructionParams& params = scene.params;
  const double h = params.voxel_mm;
  const GridSpec& grid = scene.grid();
  const std::vector<CuttingPlane>& planes = scene.planes;
  const std::vector<SectionDistanceField>& fields = scene.fields;
  SampledReconstruction out;

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
    if (out.section_plane[q] >= int(scene.real_planes)) out.section_plane[q] = -1;
    inside += out.inside[q];
  }
  out.voxels_inside = inside;
  out.voxel_betti = voxelBetti(out.inside, grid);
  return out;
}

}  // namespace xsect
