// Stage 4: arrangement and graphs (see arrange_stage.h).
#include "pipeline/arrange_stage.h"

#include <algorithm>
#include <cmath>

#include "geometry/core/polygon.h"

namespace xsect {

ArrangeStage arrangeStage(const RunConfig& c, const SectionScene& scene) {
  ArrangeStage a;
  double area = 0;
  for (std::size_t p = 0; p < scene.real_planes; ++p)
    for (const auto& s : scene.planes[p].sections) area += sectionArea(s);
  // Lattice of section points: the voxel size, coarser when it would exceed 250 000 points.
  const double spacing = std::max(c.voxel_size_mm, std::sqrt(area / 250000.0));
  a.arrangement = arrangeSections(scene.planes, spacing);
  SectionVoronoiParams vp;
  vp.slab_mm = scene.slab_mm();
  a.method2 = scene.params.method == ReconstructionMethod::section_voronoi;
  a.graphs = connectivityGraphs(scene, a.arrangement, vp, a.method2);
  for (const GraphEdge& e : a.graphs.g)
    a.g_in_g_prime = a.g_in_g_prime && std::binary_search(a.graphs.g_prime.begin(), a.graphs.g_prime.end(), e);
  return a;
}

}  // namespace xsect
