// Stage 4: arrangement and graphs (see arrange_stage.h).
#include "pipeline/arrange_stage.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "geometry/core/polygon.h"
#include "geometry/delaunay/branching_diagram.h"

namespace xsect {

double arrangementSpacing(double voxel_mm, const std::vector<CuttingPlane>& planes, std::size_t realPlanes) {
  double area = 0;
  for (std::size_t p = 0; p < realPlanes; ++p)
    for (const auto& s : planes[p].sections) area += sectionArea(s);
  // Lattice of section points: the voxel size, coarser when it would exceed 250 000 points.
  return std::max(voxel_mm, std::sqrt(area / 250000.0));
}

int edgesMissing(const std::vector<GraphEdge>& sub, const std::vector<GraphEdge>& super) {
  int missing = 0;
  for (const GraphEdge& e : sub) missing += !std::binary_search(super.begin(), super.end(), e);
  return missing;
}

ArrangeStage arrangeStage(const RunConfig& c, const SectionScene& scene, const Method& method) {
  ArrangeStage a;
  a.arrangement = arrangeSections(scene.planes, arrangementSpacing(scene.params.voxel_mm, scene.planes, scene.real_planes));
  method.requireArrangement(c, a.arrangement);
  const MethodGraphs needs = method.graphs();
  SectionVoronoiParams vp;
  vp.slab_mm = scene.slab_mm();
  a.with_g_prime = needs.g_prime;
  // Method 3's branching diagram needs the arrangement only: it is computed beside the graphs
  // (each is parallel inside but has serial stretches; multiaxial-3x40: 0.35 s and 0.80 s one
  // after the other).
  std::optional<BranchingDiagram> diagram;
  tbb::parallel_invoke([&] { a.graphs = connectivityGraphs(scene, a.arrangement, vp, a.with_g_prime); },
                       [&] {
                         if (needs.branching) diagram = branchingDiagram(scene, a.arrangement);
                       });
  if (a.with_g_prime) {
    a.g_not_in_g_prime = edgesMissing(a.graphs.g, a.graphs.g_prime);
    a.g_in_g_prime = a.g_not_in_g_prime == 0;
  }
  if (needs.branching) {
    // Method 3 (ch. 3 §1): the branching points its Delaunay triangulations add, and G''.
    BranchingDiagram& d = *diagram;
    a.branching = std::move(d.points);
    a.branching_rays = d.rays;
    a.branching_labelled = d.labelled;
    a.graphs.g_double_prime = std::move(d.g_double_prime);
    std::vector<GraphEdge>& g2 = a.graphs.g_double_prime;  // sorted and unique, as G and G' are
    std::sort(g2.begin(), g2.end());
    g2.erase(std::unique(g2.begin(), g2.end()), g2.end());
    a.with_g_double_prime = true;
    a.g_prime_not_in_g_double_prime = edgesMissing(a.graphs.g_prime, a.graphs.g_double_prime);
  }
  return a;
}

}  // namespace xsect
